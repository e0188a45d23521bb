#pragma once
// The settings `seqtopo map --preset NAME` starts from, as library values (the CLI, Python and the
// benchmarks read the same ones):
//  * default: joint histograms and patch thumbnails, each contrast-enhanced and fused (README, "The default
//    preset and why"); the pose graph draws the trajectory picture;
//  * paper: the mapping paper's pipeline (section IV): joint histograms, chi2, S = 1 - kappa D aligned as it
//    is, pruning by length ("the longest matching subsequence"), the EKF for the picture.
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
  mapping::MapConfig map;
  bool paper_trajectory = false;  // the paper's EKF draws the trajectory picture (else the pose graph)
};

// "default" or "paper"; throws std::invalid_argument naming the presets otherwise.
MapSettings map_preset(std::string_view name);
std::vector<std::string_view> map_preset_names();

}  // namespace seqtopo::pipeline
