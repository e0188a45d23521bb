#pragma once
// The baselines seqtopo is compared with, run the same way by `seqtopo map`, `seqtopo localize`, the Python
// module and the benchmarks behind the README's tables.
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "seqtopo/baseline/seqslam.hpp"
#include "seqtopo/core/dense_matrix.hpp"
#include "seqtopo/evaluation/localization_metrics.hpp"
#include "seqtopo/evaluation/loop_closure_metrics.hpp"

namespace seqtopo::pipeline {

// ---- loop closures (`seqtopo map`) ----------------------------------------------------------------

// The SeqSLAM-style matcher in self mode (loop closures within one sequence) as a list of scored pairs.
std::vector<evaluation::ScoredPair> seqslam_loop_closures(const SimilarityMatrix& similarity,
                                                          const baseline::SeqSlamConfig& config);

// The threshold with the best F1 on a precision-recall curve (the first of equals, by decreasing threshold),
// and that F1. An empty curve gives {0, 0}.
std::pair<float, double> best_f1_threshold(const std::vector<evaluation::PrPoint>& curve);

struct LoopClosureBaseline {
  evaluation::LoopClosureMetrics metrics;  // the curve of every threshold; counts at the best-F1 threshold
  std::string method;                      // which matrix, sequence, velocities and threshold
};

// The most generous reading of a single-threshold sequence matcher: the SeqSLAM-style matcher in self mode, in
// its standard configuration (localization_seqslam_config: sequence 30, velocities 0.9-1.6) and a short one
// (short_seqslam_config: sequence 10, velocities 0.8-1.25, for short loops), on every named matrix; the pairing
// with the best AUC is reported at its best-F1 threshold, against the same recall denominator
// (evaluation::images_with_earlier_partner). nullopt when no matrix is given.
std::optional<LoopClosureBaseline> seqslam_loop_closure_baseline(
    const std::vector<std::pair<std::string, const SimilarityMatrix*>>& sources, const std::vector<bool>& has_partner,
    const evaluation::SamePlace& same_place, std::size_t min_separation, unsigned threads);

// ---- localization (`seqtopo localize`) ------------------------------------------------------------

// SeqSLAM as place-recognition papers run it: sequence 30, velocities 0.9-1.6 in 8 steps, contrast window 10.
baseline::SeqSlamConfig localization_seqslam_config(unsigned threads);
// The short configuration the loop-closure baseline also tries: sequence 10, velocities 0.8-1.25.
baseline::SeqSlamConfig short_seqslam_config();
// One prediction per query frame; only frames with a whole sequence behind them are answered (the usual
// protocol), the others are "not in the map".
std::vector<evaluation::LocalizationPrediction> seqslam_localization(const SimilarityMatrix& query_x_map,
                                                                     const baseline::SeqSlamConfig& config);
// Each query frame takes its most similar map frame (localize::single_frame_matches).
std::vector<evaluation::LocalizationPrediction> single_frame_localization(const SimilarityMatrix& query_x_map);

}  // namespace seqtopo::pipeline
