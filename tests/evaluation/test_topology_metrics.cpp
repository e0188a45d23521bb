// Topology scores against hand counts and a brute-force Rand index.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "seqtopo/evaluation/topology_metrics.hpp"

namespace seqtopo::evaluation {
namespace {

// Brute-force adjusted Rand index over all pairs (Hubert & Arabie): (RI - E[RI]) / (max - E[RI]) in
// pair-count form.
double brute_ari(const std::vector<int>& a, const std::vector<int>& b) {
  double both = 0, in_a = 0, in_b = 0, pairs = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (std::size_t j = i + 1; j < a.size(); ++j) {
      pairs += 1;
      const bool sa = a[i] == a[j], sb = b[i] == b[j];
      both += sa && sb;
      in_a += sa;
      in_b += sb;
    }
  }
  const double expected = in_a * in_b / pairs;
  const double max_index = (in_a + in_b) / 2;
  if (max_index == expected) return 1.0;
  return (both - expected) / (max_index - expected);
}

TEST(TopologyMetrics, AriAgreesWithBruteForceAndIsOneForRelabeling) {
  std::mt19937 rng(8);
  for (int round = 0; round < 100; ++round) {
    const std::size_t n = 2 + rng() % 30;
    std::vector<int> a(n), b(n);
    for (auto& x : a) x = static_cast<int>(rng() % 5);
    for (auto& x : b) x = static_cast<int>(rng() % 4);
    EXPECT_NEAR(adjusted_rand_index(a, b), brute_ari(a, b), 1e-12);
    std::vector<int> relabeled(n);
    for (std::size_t k = 0; k < n; ++k) relabeled[k] = 100 - 7 * a[k];
    EXPECT_DOUBLE_EQ(adjusted_rand_index(a, relabeled), 1.0);
  }
}

TEST(TopologyMetrics, HandCountedMergesAndJunctions) {
  // 8 images; truth: 0..3 are places 10..13, 4..7 revisit them (4=10, 5=11, 6=12, 7=13).
  const std::vector<int> truth{10, 11, 12, 13, 10, 11, 12, 13};
  // map: merges 4 with 0 (right), 5 with 2 (wrong), misses 6-2 and 7-3
  const std::vector<int> labels{0, 1, 2, 3, 0, 2, 6, 7};
  const auto m = evaluate_topology(labels, {0}, truth, {10, 13}, 3);
  EXPECT_EQ(m.false_merges, 1U);   // (5, 2)
  EXPECT_EQ(m.missed_merges, 3U);  // (5, 1), (6, 2), (7, 3)
  EXPECT_EQ(m.junctions_true, 2U);
  EXPECT_EQ(m.junctions_found, 1U);
  // junction place 0 holds images 0 and 4; within 2 frames of image 4 lie images 2..6, true places
  // 12, 13, 10, 11, 12: both true junctions 10 and 13 are matched
  EXPECT_EQ(m.junctions_matched, 2U);
  EXPECT_EQ(evaluate_topology(labels, {0}, truth, {10, 13}, 3, 0).junctions_matched, 1U);
  EXPECT_THROW(evaluate_topology({0}, {}, {0, 1}, {}, 1), std::invalid_argument);
}

TEST(TopologyMetrics, CoarsensTheMapAlongRunsOfOneTruePlace) {
  // Two traversals of places 10, 11 (three images each) and a third place seen once.
  const std::vector<int> truth{10, 10, 10, 11, 11, 11, 12, 10, 10, 10, 11, 11, 11};
  // A perfect map merges one image of every revisited place with the first traversal, nothing else.
  const std::vector<int> perfect{0, 1, 2, 3, 4, 5, 6, 1, 7, 8, 9, 4, 10};
  EXPECT_EQ(coarsen_along_true_places(perfect, truth), (std::vector<int>{0, 0, 0, 1, 1, 1, 2, 0, 0, 0, 1, 1, 1}));
  const auto good = evaluate_topology(perfect, {}, truth, {}, 4);
  EXPECT_DOUBLE_EQ(good.adjusted_rand_index, 1.0);
  EXPECT_LT(good.adjusted_rand_index_frames, 0.5);  // per image, the same map looks poor
  EXPECT_EQ(good.false_merges, 0U);
  EXPECT_EQ(good.missed_merges, 0U);
  // Merging nothing leaves each place split by traversal: every cross-traversal pair of 10 and of 11 is missed.
  std::vector<int> none(truth.size());
  for (std::size_t k = 0; k < none.size(); ++k) none[k] = static_cast<int>(k);
  const auto empty = evaluate_topology(none, {}, truth, {}, 4);
  EXPECT_LT(empty.adjusted_rand_index, 1.0);
  EXPECT_EQ(empty.false_merges, 0U);
  std::size_t cross_pairs = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    for (std::size_t j = 0; j + 4 <= i; ++j) cross_pairs += truth[i] == truth[j];
  }
  EXPECT_EQ(empty.missed_merges, cross_pairs);
  // One wrong merge (image 12, place 11, with image 6, place 12) joins two true places.
  std::vector<int> wrong = perfect;
  wrong[12] = 6;
  const auto bad = evaluate_topology(wrong, {}, truth, {}, 4);
  EXPECT_LT(bad.adjusted_rand_index, good.adjusted_rand_index);
  EXPECT_EQ(bad.false_merges, 3U);  // image 6 (place 12) now shares a place with images 10..12 (place 11)
  // The same merge, tolerated by the loop-closure ground truth (image 12 is near image 6): no place joined.
  const auto near = [](std::size_t i, std::size_t j) { return (i == 12 && j == 6) || (i == 6 && j == 12); };
  const auto tolerated = evaluate_topology(wrong, {}, truth, {}, 4, 2, near);
  EXPECT_EQ(tolerated.false_merges, 0U);
  EXPECT_DOUBLE_EQ(tolerated.adjusted_rand_index, 1.0);  // image 12 still joins place 11 along its run
  // A tolerance that does not cover the pair changes nothing.
  const auto far = [](std::size_t, std::size_t) { return false; };
  EXPECT_EQ(evaluate_topology(wrong, {}, truth, {}, 4, 2, far).false_merges, 3U);
}

TEST(TopologyMetrics, OnePassAcrossAPlaceBoundaryIsNoWrongMerge) {
  const std::vector<int> truth{10, 10, 10, 11, 11, 11, 12, 10, 10, 10, 11, 11, 11};
  // The second traversal holds its place for two images, 9 and 10, on either side of the 10 | 11 boundary;
  // the first traversal's image 2 is matched there, and the loop-closure ground truth calls 2 and 10 near.
  const std::vector<int> slow{0, 1, 2, 3, 4, 5, 6, 1, 7, 2, 2, 4, 8};
  const auto near = [](std::size_t i, std::size_t j) { return std::min(i, j) == 2 && std::max(i, j) == 10; };
  const auto m = evaluate_topology(slow, {}, truth, {}, 4, 2, near);
  EXPECT_EQ(m.false_merges, 0U);
  EXPECT_DOUBLE_EQ(m.adjusted_rand_index, 1.0);
  // Counted without the pass tolerance, images 9 and 10 join places 10 and 11.
  EXPECT_EQ(coarsen_along_true_places(slow, truth, near)[0], coarsen_along_true_places(slow, truth, near)[3]);
  EXPECT_NE(coarsen_along_true_places(slow, truth, near, 4)[0], coarsen_along_true_places(slow, truth, near, 4)[3]);
  // Two images of one pass across two boundaries (images 5 and 7: places 11, 12, 10) are a wrong merge.
  std::vector<int> across = slow;
  across[7] = 5;
  EXPECT_GT(evaluate_topology(across, {}, truth, {}, 4, 2, near).false_merges, 0U);
}

}  // namespace
}  // namespace seqtopo::evaluation
