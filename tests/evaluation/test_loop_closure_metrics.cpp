// Loop-closure metrics on a hand-counted example and against a brute-force recount at every threshold.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "seqtopo/evaluation/loop_closure_metrics.hpp"

namespace seqtopo::evaluation {
namespace {

// 12 images; images 8..11 revisit 0..3 (same place iff |i - j| == 8, or i == j).
bool revisit(std::size_t i, std::size_t j) { return i == j || (i > j ? i - j : j - i) == 8; }

TEST(LoopClosureMetrics, HandCountedExample) {
  // image 8: best pair (8,0) score 5 -> TP (a worse pair (8,1) is ignored)
  // image 9: best pair (9,3) score 4 -> FP (its true partner is 1) ; image 9 is also a FN
  // image 10: (10,2) score 3 -> TP ; image 11: nothing -> FN ; image 6: (6,0) score 2 -> FP
  const std::vector<ScoredPair> pairs = {{8, 0, 5}, {8, 1, 1}, {9, 3, 4}, {10, 2, 3}, {6, 0, 2}};
  const auto m = evaluate_loop_closures(pairs, 12, revisit, 5);
  EXPECT_EQ(m.images_with_partner, 4U);
  EXPECT_EQ(m.tp, 2U);
  EXPECT_EQ(m.fp, 2U);
  EXPECT_EQ(m.fn, 2U);
  EXPECT_DOUBLE_EQ(m.precision, 0.5);
  EXPECT_DOUBLE_EQ(m.recall, 0.5);
  EXPECT_DOUBLE_EQ(m.f1, 0.5);
  // Curve (threshold: tp, fp -> P, R): 5: 1,0 -> 1, .25 ; 4: 1,1 -> .5, .25 ; 3: 2,1 -> 2/3, .5 ;
  // 2: 2,2 -> .5, .5. AP = .25*1 + 0*.5 + .25*(2/3) + 0 = 0.41666...
  ASSERT_EQ(m.curve.size(), 4U);
  EXPECT_DOUBLE_EQ(m.auc, 0.25 + 0.25 * 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(m.recall_at_100_precision, 0.25);
}

// The same example's errors, which the report marks: FP (9,3) and (6,0); misses 9 (partner 1) and 11 (partner 3).
TEST(LoopClosureMetrics, ErrorsAreTheFalsePositivesAndMissesCounted) {
  const std::vector<ScoredPair> pairs = {{8, 0, 5}, {8, 1, 1}, {9, 3, 4}, {10, 2, 3}, {6, 0, 2}};
  const auto has_partner = images_with_earlier_partner(12, revisit, 5);
  const auto e = loop_closure_errors(pairs, has_partner, revisit, 5);
  ASSERT_EQ(e.false_positives.size(), 2U);
  EXPECT_EQ(e.false_positives[0].i, 6U);
  EXPECT_EQ(e.false_positives[0].j, 0U);
  EXPECT_EQ(e.false_positives[1].i, 9U);
  EXPECT_EQ(e.false_positives[1].j, 3U);
  ASSERT_EQ(e.missed.size(), 2U);
  EXPECT_EQ(e.missed[0].i, 9U);
  EXPECT_EQ(e.missed[0].partner, 1U);
  EXPECT_EQ(e.missed[1].i, 11U);
  EXPECT_EQ(e.missed[1].partner, 3U);
  const auto m = evaluate_loop_closures(pairs, has_partner, revisit);
  EXPECT_EQ(e.false_positives.size(), m.fp);
  EXPECT_EQ(e.missed.size(), m.fn);
  // Partners are looked up for the first misses only.
  EXPECT_EQ(loop_closure_errors(pairs, has_partner, revisit, 5, 1).missed[1].partner, 11U);
}

TEST(LoopClosureMetrics, MinSeparationHidesNearbyPartners) {
  // Every image is the same place as its neighbour: with min_separation 2 nobody has a partner.
  auto near = [](std::size_t i, std::size_t j) { return (i > j ? i - j : j - i) <= 1; };
  const auto m = evaluate_loop_closures({}, 10, near, 2);
  EXPECT_EQ(m.images_with_partner, 0U);
  EXPECT_EQ(m.fn, 0U);
  EXPECT_THROW(evaluate_loop_closures({{10, 0, 1}}, 10, near, 2), std::invalid_argument);
}

TEST(LoopClosureMetrics, EarlierPartnersFromPositionsAgreeWithEveryPairTested) {
  // Routes that revisit, stand still and pass near cell borders (positions on a grid of the radius itself).
  std::mt19937 rng(7);
  for (int round = 0; round < 100; ++round) {
    const std::size_t n = 1 + rng() % 300;
    const double radius = 0.5 + (rng() % 8) * 0.25;
    std::vector<Pose2> poses(n);
    for (std::size_t i = 1; i < n; ++i) {
      const int kind = static_cast<int>(rng() % 10);
      if (kind == 0) {
        poses[i] = poses[rng() % i];  // back at an earlier pose
      } else if (kind == 1) {
        poses[i] = {radius * static_cast<double>(rng() % 9), -radius * static_cast<double>(rng() % 9), 0};
      } else {
        poses[i] = {poses[i - 1].x + (static_cast<double>(rng() % 2001) - 1000) / 1000 * radius,
                    poses[i - 1].y + (static_cast<double>(rng() % 2001) - 1000) / 1000 * radius, 0};
      }
    }
    const double r2 = radius * radius;
    const SamePlace within = [&](std::size_t i, std::size_t j) {
      const double dx = poses[i].x - poses[j].x, dy = poses[i].y - poses[j].y;
      return dx * dx + dy * dy <= r2;
    };
    const std::size_t sep = rng() % 12;
    const auto expected = images_with_earlier_partner(n, within, sep);
    EXPECT_EQ(images_with_earlier_partner(poses, radius, sep), expected) << "round " << round;
    const EarlierPartners finder = [&](std::size_t s) { return images_with_earlier_partner(poses, radius, s); };
    EXPECT_EQ(images_with_earlier_partner(n, within, finder, sep), expected);
  }
  EXPECT_THROW(images_with_earlier_partner(std::vector<Pose2>(3), 0.0, 1), std::invalid_argument);
  const EarlierPartners too_short = [](std::size_t) { return std::vector<bool>(2); };
  EXPECT_THROW(images_with_earlier_partner(3, revisit, too_short, 1), std::invalid_argument);
}

TEST(LoopClosureMetrics, AgreesWithBruteForceRecount) {
  std::mt19937 rng(99);
  for (int round = 0; round < 200; ++round) {
    const std::size_t n = 5 + rng() % 40;
    std::vector<ScoredPair> pairs;
    for (std::size_t k = rng() % 60; k > 0; --k) {
      const std::size_t i = 1 + rng() % (n - 1);
      pairs.push_back({i, rng() % i, static_cast<float>(rng() % 7)});
    }
    const std::size_t period = 3 + rng() % 10;
    auto gt = [period](std::size_t i, std::size_t j) { return (i > j ? i - j : j - i) % period == 0; };
    const std::size_t sep = 1 + rng() % 3;
    const auto m = evaluate_loop_closures(pairs, n, gt, sep);

    // brute force: the best pair of each image (largest score, then largest j), then at every
    // distinct best score recount from scratch
    auto best_of = [&](std::size_t i) {
      const ScoredPair* best = nullptr;
      for (const auto& p : pairs) {
        if (p.i == i && (!best || p.score > best->score || (p.score == best->score && p.j > best->j))) best = &p;
      }
      return best;
    };
    std::set<float, std::greater<>> thresholds;
    for (std::size_t i = 0; i < n; ++i) {
      if (const auto* b = best_of(i)) thresholds.insert(b->score);
    }
    std::size_t with_partner = 0;
    for (std::size_t i = 0; i < n; ++i) {
      bool partner = false;
      for (std::size_t j = 0; j + sep <= i; ++j) partner |= gt(i, j);
      with_partner += partner;
    }
    ASSERT_EQ(m.curve.size(), thresholds.size());
    double ap = 0, prev_r = 0, r100 = 0;
    std::size_t point = 0;
    for (float t : thresholds) {
      std::size_t tp = 0, fp = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const ScoredPair* best = best_of(i);
        if (best && best->score >= t) (gt(best->i, best->j) ? tp : fp) += 1;
      }
      const double precision = tp + fp == 0 ? 1.0 : static_cast<double>(tp) / static_cast<double>(tp + fp);
      const double recall = with_partner == 0 ? 0.0 : static_cast<double>(tp) / static_cast<double>(with_partner);
      EXPECT_DOUBLE_EQ(m.curve[point].precision, precision);
      EXPECT_DOUBLE_EQ(m.curve[point].recall, recall);
      ap += (recall - prev_r) * precision;
      prev_r = recall;
      if (fp == 0) r100 = recall;
      ++point;
    }
    EXPECT_NEAR(m.auc, ap, 1e-12);
    EXPECT_DOUBLE_EQ(m.recall_at_100_precision, r100);
  }
}

}  // namespace
}  // namespace seqtopo::evaluation
