#include "seqtopo/pipeline/presets.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <exception>
#include <stdexcept>
#include <string>

#include "seqtopo/image/image_io.hpp"

namespace seqtopo::pipeline {

MapSettings map_preset(std::string_view name) {
  MapSettings s;
  if (name == "default") return s;
  if (name != "paper") throw std::invalid_argument("unknown preset '" + std::string(name) + "' (paper or default)");
  s.descriptors = {Descriptor::joint_histogram};
  s.detect_panoramas = false;  // the paper compares its panoramas by joint histograms alone
  s.similarity.distance = Distance::chi2;
  s.paper_trajectory = true;
  s.map.score.contrast_window = 0;  // the paper aligns S = 1 - kappa D as it is
  s.map.labels.pruning.rank = mapping::PruningConfig::Rank::length_then_score;  // "the longest matching subsequence"
  // Raw S lives on another scale than enhanced scores; these were tuned on the corridor with kappa auto
  // (bench/tune_map.cpp): F1 0.872, AUC 0.773.
  s.map.search.gap = 0.3F;
  s.map.search.cap = 8.0F;
  s.map.significance.threshold = 3.0F;
  // The paper: a fixed score threshold, windows and separations in frames, the offset as given.
  s.map.significance.max_e_value.reset();
  s.map.unit = align::Unit::frames;
  s.map.phase.adapt_offset = false;
  s.map.min_revisit_places = 0;
  s.map.odometry.gate.reset();  // odometry only draws the picture (paper IV-D)
  s.map.labels.method = mapping::LabelSettings::Method::pruned_transitive;
  s.map.graph.clean = false;  // the paper reads the map from the labels as they are
  return s;
}

bool looks_panoramic(int width, int height) {
  return width > 0 && height > 0 && static_cast<double>(width) >= kPanoramaAspect * static_cast<double>(height);
}

std::vector<Descriptor> panorama_descriptors(std::vector<Descriptor> descriptors) {
  if (std::find(descriptors.begin(), descriptors.end(), Descriptor::panorama) != descriptors.end()) return descriptors;
  const auto patch = std::find(descriptors.begin(), descriptors.end(), Descriptor::patch);
  if (patch != descriptors.end()) {
    *patch = Descriptor::panorama;
  } else {
    descriptors.push_back(Descriptor::panorama);
  }
  return descriptors;
}

std::string detect_panorama_descriptors(const SequenceInput& input, std::vector<Descriptor>& descriptors) {
  if (resolve_input_kind(input) != InputKind::images) return {};
  const auto listing = list_input_images(input);
  if (listing.files.empty()) return {};
  try {
    // Its header, not the picture: a huge image is refused by the memory check before any decoding.
    const image::ImageHeader first = image::image_size(listing.files.front());
    if (!looks_panoramic(first.width, first.height)) return {};
    const auto chosen = panorama_descriptors(descriptors);
    if (chosen == descriptors) return {};
    descriptors = chosen;
    return fmt::format("{} x {} images look like 360-degree panoramas (at least {}:1): descriptors {}", first.width,
                       first.height, kPanoramaAspect, descriptor_names(chosen));
  } catch (const std::exception&) {
    return {};  // an unreadable image is reported by the run itself
  }
}

std::vector<std::string_view> map_preset_names() { return {"default", "paper"}; }

}  // namespace seqtopo::pipeline
