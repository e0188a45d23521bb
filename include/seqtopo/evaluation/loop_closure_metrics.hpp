#pragma once
// Loop-closure accuracy counted per image, as in the loop-closure literature (INTERFACE.md):
//  * image i is a detection when some candidate pair (i, j) has j < i; its best-scoring pair counts;
//  * the detection is a true positive when the ground truth says i and j are the same place, else a
//    false positive;
//  * an image with a ground-truth partner j < i (at least min_separation frames earlier) but no
//    true-positive detection is a false negative.
// The PR curve sweeps a threshold over the detections' scores (a detection counts when its score is
// >= the threshold). AUC is the average precision: sum over the curve of (recall step) x precision.
// recall_at_100_precision is the highest recall at a threshold with no false positive (0 if none).
#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "seqtopo/core/pose2.hpp"

namespace seqtopo::evaluation {

struct ScoredPair {
  std::size_t i = 0, j = 0;  // i > j
  float score = 0;
};

struct PrPoint {
  float threshold = 0;
  double precision = 0, recall = 0;
};

struct LoopClosureMetrics {
  std::size_t tp = 0, fp = 0, fn = 0;
  double precision = 0, recall = 0, f1 = 0, auc = 0, recall_at_100_precision = 0;
  std::size_t images_with_partner = 0;  // the recall denominator
  std::vector<PrPoint> curve;           // by decreasing threshold
};

// The precision-recall sweep shared by loop closures and localization: detections sorted by
// decreasing score, one curve point per distinct score (a threshold admits every score >= it),
// AUC as average precision, and the highest recall with no false positive.
struct PrSweep {
  std::vector<PrPoint> curve;  // by decreasing threshold
  double auc = 0, recall_at_100_precision = 0;
};
// scores[k] and correct[k] describe detection k; `positives` is the recall denominator.
PrSweep sweep_precision_recall(const std::vector<float>& scores, const std::vector<bool>& correct,
                               std::size_t positives);

// Same-place relation of the ground truth (symmetric).
using SamePlace = std::function<bool(std::size_t, std::size_t)>;

// The best-scoring pair (i, j < i) of every image i, by increasing i. Ties: the larger j.
std::vector<ScoredPair> best_pair_per_image(const std::vector<ScoredPair>& pairs);

// The recall denominator: whether each image has a ground-truth partner at least min_separation frames earlier.
// From the relation alone this tests every pair, O(N^2); from the true positions and the radius of the relation it
// looks only in the grid cells (radius wide) around each image, near O(N) along a route: the two agree exactly.
std::vector<bool> images_with_earlier_partner(std::size_t images, const SamePlace& same_place,
                                              std::size_t min_separation);
std::vector<bool> images_with_earlier_partner(std::span<const Pose2> positions, double radius,
                                              std::size_t min_separation);
// The finder a ground truth may offer for the same; the overload below uses it when given, else the relation.
using EarlierPartners = std::function<std::vector<bool>(std::size_t min_separation)>;
std::vector<bool> images_with_earlier_partner(std::size_t images, const SamePlace& same_place,
                                              const EarlierPartners& finder, std::size_t min_separation);

LoopClosureMetrics evaluate_loop_closures(const std::vector<ScoredPair>& pairs, std::size_t images,
                                          const SamePlace& same_place, std::size_t min_separation);
// The same with the recall denominator found beforehand (one entry per image).
LoopClosureMetrics evaluate_loop_closures(const std::vector<ScoredPair>& pairs,
                                          const std::vector<bool>& has_earlier_partner, const SamePlace& same_place);

// Where the detections are wrong, counted as evaluate_loop_closures counts them: each false positive (an image's
// best pair that is not the same place) and each missed revisit (an image with an earlier partner but no true
// positive), by increasing image. A missed image is shown with its nearest true partner at least min_separation
// frames earlier (`partner`), looked up for the first `max_partners` misses only (the others: partner = i).
struct MissedRevisit {
  std::size_t i = 0, partner = 0;
};
struct LoopClosureErrors {
  std::vector<ScoredPair> false_positives;
  std::vector<MissedRevisit> missed;
};
LoopClosureErrors loop_closure_errors(const std::vector<ScoredPair>& pairs,
                                      const std::vector<bool>& has_earlier_partner, const SamePlace& same_place,
                                      std::size_t min_separation, std::size_t max_partners = 1000);

}  // namespace seqtopo::evaluation
