// Localization metrics: a small case worked by hand, and random cases against a brute-force threshold sweep.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <stdexcept>

#include "seqtopo/evaluation/localization_metrics.hpp"

namespace seqtopo::evaluation {
namespace {

LocalizationPrediction predict(std::size_t map, float score, std::vector<std::size_t> candidates = {}) {
  if (candidates.empty()) candidates = {map};
  return {map, score, std::move(candidates)};
}

TEST(LocalizationMetrics, WorkedExample) {
  // 5 query frames, same-index truth with tolerance 1, 6 map frames:
  //   q0 -> 0 (correct, 0.9)   q1 -> 4 (wrong, 0.8; its 2nd candidate 2 is correct)
  //   q2 -> 3 (correct, 0.7)   q3 not in the map   q4 -> 1 (wrong, 0.2)
  std::vector<LocalizationPrediction> p{predict(0, 0.9F), predict(4, 0.8F, {4, 2}), predict(3, 0.7F),
                                        LocalizationPrediction{}, predict(1, 0.2F)};
  const auto m = evaluate_localization(p, LocalizationTruth::same_index(5, 6), 1);
  EXPECT_EQ(m.queries, 5U);
  EXPECT_EQ(m.queries_with_match, 5U);
  EXPECT_EQ(m.predicted, 4U);
  EXPECT_EQ(m.correct, 2U);
  EXPECT_DOUBLE_EQ(m.recall_at_1, 2.0 / 5);
  EXPECT_DOUBLE_EQ(m.recall_at_5, 3.0 / 5);
  EXPECT_DOUBLE_EQ(m.precision, 2.0 / 4);
  EXPECT_DOUBLE_EQ(m.recall, 2.0 / 5);
  // Sweep: 0.9 -> P 1 R 0.2; 0.8 -> P 1/2 R 0.2; 0.7 -> P 2/3 R 0.4; 0.2 -> P 1/2 R 0.4.
  ASSERT_EQ(m.curve.size(), 4U);
  EXPECT_DOUBLE_EQ(m.curve[2].precision, 2.0 / 3);
  EXPECT_DOUBLE_EQ(m.auc, 0.2 * 1.0 + 0.2 * (2.0 / 3));
  EXPECT_DOUBLE_EQ(m.recall_at_100_precision, 0.2);
}

TEST(LocalizationMetrics, QueriesWithoutTruthOnlyAddFalsePositives) {
  // Map of 3 frames, query of 5: frames 3 and 4 have no true match.
  std::vector<LocalizationPrediction> p{predict(0, 1.0F), predict(1, 0.9F), predict(2, 0.8F), predict(2, 0.95F),
                                        LocalizationPrediction{}};
  const auto m = evaluate_localization(p, LocalizationTruth::same_index(5, 3), 0);
  EXPECT_EQ(m.queries_with_match, 3U);
  EXPECT_DOUBLE_EQ(m.recall_at_1, 1.0);
  EXPECT_DOUBLE_EQ(m.precision, 3.0 / 4);
  EXPECT_DOUBLE_EQ(m.recall_at_100_precision, 1.0 / 3);  // q3's 0.95 is the second-best score
}

TEST(LocalizationMetrics, PairsTruthAndCsv) {
  const auto pairs = parse_pairs_csv("query,map\n0, 5\n\n1,7\r\n1,9\n");
  ASSERT_EQ(pairs.size(), 3U);
  EXPECT_EQ(pairs[2], (std::pair<std::size_t, std::size_t>{1, 9}));
  const auto t = LocalizationTruth::from_pairs(pairs, 3, 10);
  EXPECT_TRUE(t.correct(0, 5, 0));
  EXPECT_TRUE(t.correct(0, 4, 1));
  EXPECT_FALSE(t.correct(0, 3, 1));
  EXPECT_TRUE(t.correct(1, 8, 1));
  EXPECT_FALSE(t.correct(2, 0, 5));
  EXPECT_EQ(parse_pairs_csv("3,4\n").size(), 1U);  // the header is optional
  EXPECT_THROW(parse_pairs_csv("query,map\n1;2\n"), std::invalid_argument);
  EXPECT_THROW(parse_pairs_csv("1,-2\n"), std::invalid_argument);
  EXPECT_THROW(parse_pairs_csv("1,2,3\n"), std::invalid_argument);
  EXPECT_THROW(parse_pairs_csv("1,2\nquery,map\n"), std::invalid_argument);
  EXPECT_THROW(LocalizationTruth::from_pairs({{3, 0}}, 3, 10), std::invalid_argument);
  EXPECT_THROW(LocalizationTruth::from_pairs({{0, 10}}, 3, 10), std::invalid_argument);
}

TEST(LocalizationMetrics, RejectsMismatchedSizes) {
  EXPECT_THROW(evaluate_localization({predict(0, 1.0F)}, LocalizationTruth::same_index(2, 2), 0),
               std::invalid_argument);
  EXPECT_THROW(evaluate_localization({predict(5, 1.0F)}, LocalizationTruth::same_index(1, 2), 0),
               std::invalid_argument);
}

TEST(LocalizationMetrics, CurveEqualsBruteForceSweep) {
  std::mt19937 rng(21);
  for (int round = 0; round < 50; ++round) {
    const std::size_t nq = 1 + rng() % 30, nm = 1 + rng() % 30, tol = rng() % 3;
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    for (std::size_t q = 0; q < nq; ++q) {
      if (rng() % 4 != 0) pairs.emplace_back(q, rng() % nm);
    }
    const auto truth = LocalizationTruth::from_pairs(pairs, nq, nm);
    std::vector<LocalizationPrediction> p(nq);
    for (auto& x : p) {
      if (rng() % 5 != 0) x = predict(rng() % nm, static_cast<float>(rng() % 6));  // ties are common
    }
    const auto m = evaluate_localization(p, truth, tol);
    std::size_t with_match = 0;
    for (const auto& v : truth.truth) with_match += v.empty() ? 0 : 1;
    std::set<float> thresholds;
    for (const auto& x : p) {
      if (x.map) thresholds.insert(x.score);
    }
    ASSERT_EQ(m.curve.size(), thresholds.size());
    double auc = 0, previous = 0, r100 = 0;
    std::size_t k = 0;
    for (auto it = thresholds.rbegin(); it != thresholds.rend(); ++it, ++k) {
      std::size_t tp = 0, fp = 0;
      for (std::size_t q = 0; q < nq; ++q) {
        if (!p[q].map || p[q].score < *it) continue;
        bool ok = false;
        for (std::size_t t : truth.truth[q]) ok = ok || (*p[q].map + tol >= t && *p[q].map <= t + tol);
        (ok ? tp : fp) += 1;
      }
      const double precision = static_cast<double>(tp) / static_cast<double>(tp + fp);
      const double recall = with_match == 0 ? 0.0 : static_cast<double>(tp) / static_cast<double>(with_match);
      EXPECT_DOUBLE_EQ(m.curve[k].precision, precision);
      EXPECT_DOUBLE_EQ(m.curve[k].recall, recall);
      auc += (recall - previous) * precision;
      previous = recall;
      if (fp == 0) r100 = recall;
    }
    EXPECT_NEAR(m.auc, auc, 1e-12);
    EXPECT_DOUBLE_EQ(m.recall_at_100_precision, r100);
  }
}

}  // namespace
}  // namespace seqtopo::evaluation
