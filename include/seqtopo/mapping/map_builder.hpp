#pragma once
// The mapping paper end to end, from a similarity matrix: forward and reverse self alignments with
// the score cap -> per-column pruning -> transitive labels -> topological map. One call, pure.
#include <optional>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/core/dense_matrix.hpp"
#include "seqtopo/mapping/pruning.hpp"
#include "seqtopo/mapping/topological_map.hpp"

namespace seqtopo::mapping {

struct MapConfig {
  float gap = 1.0F;                 // penalty per skipped image, both sequences [similarity units]
  std::optional<float> cap = 6.0F;  // cap on the cumulative score (paper IV-B)
  float threshold = 4.0F;           // minimum alignment score for a revisit
  std::size_t min_separation = 10;  // [frames] pairs closer than this in time never count
  bool reverse = true;              // also look for paths revisited in the opposite direction
  PruningConfig pruning;
  TopologyConfig topology;
  unsigned threads = 2;
};

struct MapResult {
  std::vector<align::LocalAlignment> alignments;  // best first, forward and reverse merged
  PruningResult pruning;
  TopologicalMap map;
  double seconds_align = 0, seconds_prune_label = 0;
};

// Throws std::invalid_argument for a non-square or empty matrix.
MapResult build_map(const SimilarityMatrix& similarity, const MapConfig& config = {});

}  // namespace seqtopo::mapping
