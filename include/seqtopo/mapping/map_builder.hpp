#pragma once
// The mapping paper end to end, from a similarity matrix: forward and reverse self alignments with
// the score cap -> per-column pruning -> transitive labels -> topological map. One call, pure.
// build_map_from_scores is the same pipeline after the scores, on any score source (scores streamed from
// descriptors, scale/streaming_similarity.hpp), for sequences whose N x N matrix would not fit.
#include <optional>
#include <span>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/align/score_source.hpp"
#include "seqtopo/core/dense_matrix.hpp"
#include "seqtopo/mapping/odometry_gate.hpp"
#include "seqtopo/mapping/pruning.hpp"
#include "seqtopo/mapping/topological_map.hpp"

namespace seqtopo::mapping {

struct MapConfig {
  // Local contrast enhancement before alignment (similarity/contrast_enhancement.hpp): the aligned
  // score is 0.5 (E + E^T) - contrast_offset, in standard deviations of each row's neighbourhood.
  // contrast_window = 0 aligns the raw S = 1 - kappa D, as the paper does.
  // Defaults chosen on the real corridor loop and on Nordland summer+winter (bench/tune_map.cpp,
  // README "Accuracy on real data").
  std::size_t contrast_window = 10;  // [frames]
  float contrast_offset = 0.5F;      // [standard deviations]
  float gap = 1.5F;                  // penalty per skipped image, both sequences [score units]
  std::optional<float> cap = 40.0F;  // cap on the cumulative score (paper IV-B)
  // Minimum alignment score for a revisit. The real sequences give the same result anywhere in 8..20;
  // the simulated worlds (bench/worlds.sh) need 20 to drop short chance alignments.
  float threshold = 20.0F;
  std::size_t min_separation = 10;  // [frames] pairs closer than this in time never count
  bool reverse = true;              // also look for paths revisited in the opposite direction
  // exact: the scalar reference engine (align/smith_waterman.hpp, a float table of N x N cells);
  // fast: the vectorized linear-memory engine (align/fast_alignment.hpp) on scores quantized to
  // 1/512 of a unit with the default cap: the same alignments as the exact engine on those scores.
  enum class Engine { exact, fast };
  Engine engine = Engine::exact;
  // Applied when odometry is given to build_map: alignments it contradicts are dropped before pruning.
  // Chosen on the simulated worlds (bench/worlds.sh); the real sequences in the README have no odometry.
  std::optional<OdometryGate> odometry_gate = OdometryGate{};
  PruningConfig pruning;
  TopologyConfig topology;
  unsigned threads = 2;
};

struct MapResult {
  SimilarityMatrix scores;                        // what was aligned (S, or its contrast-enhanced form); empty
                                                  // from build_map_from_scores
  std::vector<align::LocalAlignment> alignments;  // best first, forward and reverse merged
  std::vector<align::LocalAlignment> rejected;    // found, but contradicted by the odometry (not in `alignments`)
  PruningResult pruning;
  TopologicalMap map;
  double seconds_align = 0, seconds_prune_label = 0;
};

// Throws std::invalid_argument for a non-square or empty matrix, or odometry of another length.
// `odometry` (one pose per image, or empty) feeds config.odometry_gate.
MapResult build_map(const SimilarityMatrix& similarity, const MapConfig& config = {},
                    std::span<const Pose2> odometry = {});

// Several sensors or descriptors of the same sequence, fused: each matrix is contrast-enhanced on its
// own (so their scales need not agree) and the enhanced scores are averaged before the offset is
// applied; without contrast enhancement the raw matrices are averaged. All must be N x N.
MapResult build_map(const std::vector<SimilarityMatrix>& similarities, const MapConfig& config = {},
                    std::span<const Pose2> odometry = {});

// The pipeline after the scores: `scores` is what is aligned as it is (contrast_window and contrast_offset
// are not applied again). Throws std::invalid_argument for an empty or non-square source, or odometry of
// another length. The exact engine fills an N x N table whatever the source; a source that is not held
// in memory wants Engine::fast (1/8 byte per cell, docs/engine.md). seconds_align includes the reads of `scores`.
MapResult build_map_from_scores(const align::ScoreSource& scores, const MapConfig& config = {},
                                std::span<const Pose2> odometry = {});

// The engine settings build_map aligns with: the config's gap, cap, threshold and min_separation, self.
align::AlignConfig align_config(const MapConfig& config);

// The fused score matrix that build_map aligns.
SimilarityMatrix alignment_scores(const std::vector<SimilarityMatrix>& similarities, const MapConfig& config);

}  // namespace seqtopo::mapping
