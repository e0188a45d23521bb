#include "seqtopo/pipeline/presets.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace seqtopo::pipeline {

MapSettings map_preset(std::string_view name) {
  MapSettings s;
  if (name == "default") return s;
  if (name != "paper") throw std::invalid_argument("unknown preset '" + std::string(name) + "' (paper or default)");
  s.descriptors = {Descriptor::joint_histogram};
  s.detect_panoramas = false;  // the paper compares its panoramas by joint histograms alone
  s.similarity.distance = Distance::chi2;
  s.paper_trajectory = true;
  s.map.contrast_window = 0;                                             // the paper aligns S = 1 - kappa D as it is
  s.map.pruning.rank = mapping::PruningConfig::Rank::length_then_score;  // "the longest matching subsequence"
  // Raw S lives on another scale than enhanced scores; these were tuned on the corridor with kappa auto
  // (bench/tune_map.cpp): F1 0.872, AUC 0.773.
  s.map.gap = 0.3F;
  s.map.cap = 8.0F;
  s.map.threshold = 3.0F;
  // The paper: a fixed score threshold, windows and separations in frames, the offset as given.
  s.map.max_e_value.reset();
  s.map.place_units = false;
  s.map.adapt_offset = false;
  s.map.min_revisit_places = 0;
  s.map.odometry_gate.reset();  // odometry only draws the picture (paper IV-D)
  s.map.labelling = mapping::MapConfig::Labelling::pruned_transitive;
  s.map.clean_graph = false;  // the paper reads the map from the labels as they are
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

std::vector<std::string_view> map_preset_names() { return {"default", "paper"}; }

}  // namespace seqtopo::pipeline
