#pragma once
// The settings `seqtopo map --preset NAME` starts from, as library values (the CLI, Python and the
// benchmarks read the same ones):
//  * default: joint histograms and patch thumbnails, each contrast-enhanced and fused (README, "The default
//    preset and why"); the pose graph draws the trajectory picture;
//  * paper: the mapping paper's pipeline (section IV): joint histograms, chi2, S = 1 - kappa D aligned as it
//    is, pruning by length ("the longest matching subsequence"), the EKF for the picture.
#include <string>
#include <string_view>
#include <vector>

#include "seqtopo/mapping/map_builder.hpp"
#include "seqtopo/pipeline/sequence_similarity.hpp"

namespace seqtopo::pipeline {

struct MapSettings {
  SimilarityConfig similarity;
  // One similarity matrix per descriptor; several are fused (mapping::build_map). A descriptors.npy or
  // similarity.npy input is one matrix whatever this says.
  std::vector<Descriptor> descriptors{Descriptor::joint_histogram, Descriptor::patch};
  // An image input whose first image is a 360-degree panorama (looks_panoramic) is compared by the
  // heading-invariant panorama signature instead of the patch thumbnail (panorama_descriptors): a place passed
  // the other way round is the same panorama shifted by half its width, which a thumbnail does not see
  // (docs/simulator.md). Off when the descriptors are chosen (--descriptor) and under the paper preset.
  bool detect_panoramas = true;
  mapping::MapConfig map;
  bool paper_trajectory = false;  // the paper's EKF draws the trajectory picture (else the pose graph)
};

// Whether an image of width x height [pixels] is a 360-degree panorama: at least kPanoramaAspect times as wide as
// it is high (seqtopo simulate writes 360 x 60, an unwarped omnidirectional image is typically 4-8:1; camera
// images are 4:3 to 2:1).
inline constexpr double kPanoramaAspect = 3.0;
bool looks_panoramic(int width, int height);
// The descriptors for panoramas: `descriptors` with patch replaced by panorama (and panorama added when neither
// is there); unchanged when panorama is already in.
std::vector<Descriptor> panorama_descriptors(std::vector<Descriptor> descriptors);
// `descriptors` for an image input whose first image (by its header) looks panoramic: panorama_descriptors of
// them, and the note that says so (empty, and `descriptors` unchanged, otherwise or when the image is unreadable:
// the run itself reports that).
std::string detect_panorama_descriptors(const SequenceInput& input, std::vector<Descriptor>& descriptors);

// "default" or "paper"; throws std::invalid_argument naming the presets otherwise.
MapSettings map_preset(std::string_view name);
std::vector<std::string_view> map_preset_names();

}  // namespace seqtopo::pipeline
