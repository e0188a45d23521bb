// Several descriptors in one localization: the fused scores against their definition computed here, the weights
// against the shift each descriptor's scores show on a planted revisit, a blind descriptor left out, and the
// online localizer's fusion against the offline one.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <span>
#include <stdexcept>
#include <vector>

#include "common/sanitizers.hpp"
#include "seqtopo/localize/localize.hpp"
#include "seqtopo/localize/online_localizer.hpp"

namespace seqtopo::localize {
namespace {

// Query frames 0..89 drive map frames 30..119 (query q at map q + 30); every cell is Gaussian noise, the true
// pairs `shift` higher.
SimilarityMatrix planted(double shift, unsigned seed, std::size_t rows = 90, std::size_t cols = 160) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(0.0F, 1.0F);
  SimilarityMatrix s(rows, cols);
  for (auto& v : s.values) v = g(rng);
  for (std::size_t q = 0; q < rows && q + 30 < cols; ++q) s(q, q + 30) += static_cast<float>(shift);
  return s;
}

double recall_at_1(const std::vector<FrameMatch>& frames) {
  double right = 0;
  for (std::size_t q = 0; q < frames.size(); ++q)
    right += std::abs(static_cast<long>(frames[q].map) - (long(q) + 30)) <= 2;
  return right / static_cast<double>(frames.size());
}

// The frames answered in the map and right: what the evidence itself localizes (the guesses carried on along the
// route from them are not counted).
double recall_in_map(const std::vector<FrameMatch>& frames) {
  double right = 0;
  for (std::size_t q = 0; q < frames.size(); ++q)
    right += frames[q].covered && std::abs(static_cast<long>(frames[q].map) - (long(q) + 30)) <= 2;
  return right / static_cast<double>(frames.size());
}

TEST(Fusion, EqualWeightsAverageTheEnhancedRowsThenSubtractTheOffset) {
  LocalizeConfig c;
  c.score.contrast_window = 7;
  c.score.contrast_offset = 0.6F;
  const std::vector<SimilarityMatrix> ss{planted(2.0, 1), planted(0.5, 2)};
  LocalizeConfig unshifted = c;
  unshifted.score.contrast_offset = 0;
  const SimilarityMatrix a = score_matrix(ss[0], unshifted), b = score_matrix(ss[1], unshifted);
  const SimilarityMatrix fused = fused_score_matrix(ss, c);
  for (std::size_t k = 0; k < fused.values.size(); ++k) {
    ASSERT_NEAR(fused.values[k], (a.values[k] + b.values[k]) / 2 - 0.6F, 1e-5) << k;
  }
  const std::vector<double> weights{3.0, 1.0};
  const SimilarityMatrix weighted = fused_score_matrix(ss, c, weights);
  for (std::size_t k = 0; k < weighted.values.size(); ++k) {
    ASSERT_NEAR(weighted.values[k], 0.75 * a.values[k] + 0.25 * b.values[k] - 0.6, 1e-5) << k;
  }
  // One matrix is score_matrix itself.
  EXPECT_EQ(fused_score_matrix(std::span(ss).first(1), c).values, score_matrix(ss[0], c).values);
  // The localization keeps the fused enhanced scores it aligned, before the offset: fused_score_matrix's, bit for
  // bit (each similarity enhanced once there, for the weights and the fusion alike), with the weights it chose; and
  // the answers are those of the fused scores aligned on their own.
  const LocalizeResult r = localize_sequence(ss, c);
  EXPECT_EQ(r.fused_enhanced.values, fused_score_matrix(ss, unshifted, r.descriptor_weights).values);
  EXPECT_EQ(r.descriptor_weights, descriptor_weights(ss, c));
  const LocalizeResult again = localize_scores(fused_score_matrix(ss, c, r.descriptor_weights), c);
  ASSERT_EQ(r.frames.size(), again.frames.size());
  for (std::size_t q = 0; q < r.frames.size(); ++q) {
    EXPECT_EQ(r.frames[q].map, again.frames[q].map);
    EXPECT_EQ(r.frames[q].confidence, again.frames[q].confidence);
  }
  EXPECT_TRUE(localize_sequence(std::span(ss).first(1), c).fused_enhanced.empty());
  // The row version gives the matrix's rows.
  std::vector<float> row(ss[0].cols), scratch(ss[0].cols);
  for (std::size_t i = 0; i < ss[0].rows; i += 17) {
    const float* rows[2] = {ss[0].row(i).data(), ss[1].row(i).data()};
    fused_score_row(rows, ss[0].cols, c, row.data(), scratch.data(), weights);
    for (std::size_t j = 0; j < row.size(); ++j) ASSERT_EQ(row[j], weighted(i, j)) << i << " " << j;
  }
}

TEST(Fusion, WeighsEachDescriptorByTheShiftOfItsScoresOnTheRevisit) {
  SEQTOPO_SKIP_UNDER_SANITIZERS("30 localizations of ten seeds");
  // Three descriptors see the same revisit with shifts 3, 1.5 and 0.75 (in noise of 1): their weights follow the
  // shifts, as the matched filter's do, over ten seeds.
  for (unsigned seed = 0; seed < 10; ++seed) {
    const std::vector<SimilarityMatrix> ss{planted(3.0, 10 + seed), planted(1.5, 40 + seed), planted(0.75, 70 + seed)};
    const std::vector<double> w = descriptor_weights(ss, {});
    ASSERT_EQ(w.size(), 3U);
    EXPECT_GT(w[0], w[1]) << seed;
    EXPECT_GT(w[1], w[2]) << seed;
    EXPECT_NEAR(w[0] / w[1], 2.0, 0.6) << seed;
    EXPECT_NEAR(w[1] / w[2], 2.0, 1.0) << seed;
  }
}

TEST(Fusion, ABlindDescriptorIsLeftOutAndAWeakOneCostsNothing) {
  SEQTOPO_SKIP_UNDER_SANITIZERS("60 localizations of ten seeds");
  std::size_t left_out = 0;
  double recall_alone = 0, recall_weighted = 0, in_map_weighted = 0, in_map_equal = 0;
  for (unsigned seed = 0; seed < 10; ++seed) {
    const SimilarityMatrix strong = planted(1.6, 100 + seed);
    const SimilarityMatrix noise = planted(0.0, 200 + seed);
    const SimilarityMatrix weak = planted(0.3, 300 + seed);
    const LocalizeResult alone = localize_sequence(strong);
    const std::vector<SimilarityMatrix> with_noise{noise, strong};
    const LocalizeResult blind = localize_sequence(with_noise);
    // Pure noise is left out unless a chance alignment of its own passes the cut (about one search in a hundred:
    // seed 8 here, E 0.0036), and then it weighs a fraction of the seeing one.
    if (blind.blind_descriptors == std::vector<std::size_t>{0}) {
      ++left_out;
      EXPECT_EQ(blind.descriptor_weights.front(), 0.0);
      EXPECT_DOUBLE_EQ(recall_at_1(blind.frames), recall_at_1(alone.frames)) << seed;
    } else {
      EXPECT_LT(blind.descriptor_weights[0], 0.5 * blind.descriptor_weights[1]) << seed;
    }
    // A descriptor that barely sees the revisit, averaged in equally, costs the frames the evidence puts in the map;
    // weighted it does not.
    const std::vector<SimilarityMatrix> with_weak{strong, weak};
    const LocalizeResult weighted = localize_sequence(with_weak);
    const LocalizeResult equal = localize_scores(fused_score_matrix(with_weak, {}), {});
    recall_alone += recall_at_1(alone.frames);
    recall_weighted += recall_at_1(weighted.frames);
    in_map_weighted += recall_in_map(weighted.frames);
    in_map_equal += recall_in_map(equal.frames);
  }
  EXPECT_GE(left_out, 9U);
  EXPECT_GE(recall_weighted / 10, recall_alone / 10 - 0.01);
  EXPECT_GT(in_map_weighted, in_map_equal);
}

TEST(Fusion, OnlineFusesAsOfflineOnceTheWeightsAreFitted) {
  const std::vector<SimilarityMatrix> ss{planted(1.5, 7, 160), planted(0.4, 8, 160)};
  const LocalizeConfig c;
  OnlineLocalizer online(ss[0].cols, c, 2);
  std::vector<OnlineEstimate> estimates;
  for (std::size_t i = 0; i < ss[0].rows; ++i) {
    const std::span<const float> rows[2] = {ss[0].row(i), ss[1].row(i)};
    estimates.push_back(online.feed_descriptors(rows));
  }
  // After the last refit (at 128 frames) the weights are the offline ones of those frames.
  const std::vector<SimilarityMatrix> first{
      SimilarityMatrix(128, ss[0].cols, std::vector<float>(ss[0].values.begin(), ss[0].values.begin() + 128 * 160)),
      SimilarityMatrix(128, ss[1].cols, std::vector<float>(ss[1].values.begin(), ss[1].values.begin() + 128 * 160))};
  EXPECT_EQ(online.weights(), descriptor_weights(first, c));
  // Online guesses follow the revisit once its evidence has built up.
  double right = 0;
  for (std::size_t q = 20; q < 90; ++q) right += std::abs(static_cast<long>(estimates[q].map) - (long(q) + 30)) <= 2;
  EXPECT_GT(right / 70, 0.9);
  // One row per descriptor, or the localizer refuses.
  const std::span<const float> one[1] = {ss[0].row(0)};
  EXPECT_THROW(online.feed_descriptors(one), std::invalid_argument);
  EXPECT_THROW(OnlineLocalizer(10, c, 0), std::invalid_argument);
  const std::vector<SimilarityMatrix> mismatched{planted(1.0, 1, 10, 20), planted(1.0, 1, 10, 21)};
  EXPECT_THROW(fused_score_matrix(mismatched, c), std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::localize
