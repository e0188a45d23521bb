#pragma once
// Accuracy of localizing query frames in a map (INTERFACE.md, `seqtopo localize`), counted per query frame
// as in the place-recognition literature:
//  * ground truth: for each query frame, the map frames showing the same place (possibly none);
//  * a prediction is correct when it lies within +-tolerance frames of one of them;
//  * recall@k: the fraction of query frames with a true match whose k best candidates include a correct one
//    (the score threshold plays no part; a frame "not in the map" counts as a miss);
//  * PR curve: a threshold is swept over the predictions' scores; accepted = predictions scoring >= it,
//    precision = correct / accepted (1 when none is accepted), recall = correct / query frames with a true
//    match. A prediction for a frame that has no true match is always a false positive.
//  * auc: average precision, sum over the curve of (recall step) x precision;
//  * recall_at_100_precision: the highest recall at a threshold with no false positive (0 if none).
#include <cstddef>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "seqtopo/evaluation/loop_closure_metrics.hpp"

namespace seqtopo::evaluation {

// truth[q]: the map frames of query frame q's place, sorted; empty = q is not in the map.
struct LocalizationTruth {
  std::size_t map_frames = 0;
  std::vector<std::vector<std::size_t>> truth;

  // Query q matches map frame q (when q < map_frames); the tolerance is applied at evaluation.
  static LocalizationTruth same_index(std::size_t query_frames, std::size_t map_frames);
  // From (query, map) pairs; throws std::invalid_argument on a pair outside the sizes.
  static LocalizationTruth from_pairs(const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                                      std::size_t query_frames, std::size_t map_frames);
  // Within +-tolerance of a true map frame of query q.
  bool correct(std::size_t query, std::size_t map, std::size_t tolerance) const;
};

// Parses CSV text `query,map` (a header line is optional; blank lines and spaces around fields are
// ignored). Throws std::invalid_argument with "line N: ..." on a malformed line.
std::vector<std::pair<std::size_t, std::size_t>> parse_pairs_csv(std::string_view text);

struct LocalizationPrediction {
  std::optional<std::size_t> map;       // nullopt = "not in the map"
  float score = 0;                      // higher = more confident
  std::vector<std::size_t> candidates;  // best first (candidates[0] == *map when given); for recall@k
};

struct LocalizationMetrics {
  std::size_t queries = 0, queries_with_match = 0, predicted = 0, correct = 0;
  double recall_at_1 = 0, recall_at_5 = 0;
  double precision = 0, recall = 0;  // every prediction accepted
  double auc = 0, recall_at_100_precision = 0;
  std::vector<PrPoint> curve;  // by decreasing threshold
};

// Throws std::invalid_argument when the sizes disagree.
LocalizationMetrics evaluate_localization(const std::vector<LocalizationPrediction>& predictions,
                                          const LocalizationTruth& truth, std::size_t tolerance);

}  // namespace seqtopo::evaluation
