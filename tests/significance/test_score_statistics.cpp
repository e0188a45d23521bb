// The statistics' fit on scores with a known law, against a second estimator (the exponential tail's
// maximum-likelihood rate); the search area against a brute-force count; the path score of a hand-worked
// alignment.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "seqtopo/significance/score_statistics.hpp"

namespace seqtopo::significance {
namespace {

// The `count` best scores of a search whose chance alignments above s number K * area * exp(-lambda s): the
// points of a Poisson process of that intensity, best first.
std::vector<double> poisson_scores(double lambda, double k, double area, std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::exponential_distribution<double> gap(1.0);
  std::vector<double> scores;
  double mass = 0;  // expected number of chance alignments above the next score
  for (std::size_t r = 0; r < count; ++r) {
    mass += gap(rng);
    scores.push_back((std::log(k * area) - std::log(mass)) / lambda);
  }
  return scores;
}

// The exponential tail's rate from the mean excess of all scores over the lowest (no real alignment among
// them): a second estimator, without the fit's ranks.
double mean_excess_rate(const std::vector<double>& scores) {
  double sum = 0;
  for (double s : scores) sum += s - scores.back();
  return static_cast<double>(scores.size() - 1) / sum;
}

TEST(ScoreStatistics, TheFitRecoversLambdaAndKOfAPoissonTail) {
  for (std::uint32_t seed = 1; seed <= 5; ++seed) {
    for (double lambda : {0.3, 1.2}) {
      const double k = 0.05, area = 1e6;
      const auto scores = poisson_scores(lambda, k, area, 1000, seed);
      const auto fit = fit_declumped_scores(scores, area);
      ASSERT_TRUE(fit.valid()) << seed;
      // About 1000 chance alignments: lambda within 4 standard errors (3 % each), and close to the second
      // estimator on the same sample.
      EXPECT_NEAR(fit.lambda, lambda, 0.12 * lambda) << seed;
      EXPECT_NEAR(fit.lambda, mean_excess_rate(scores), 0.03 * lambda) << seed;
      // K is exp of an intercept: a 10 % error in lambda moves it by a factor; the E-value of the scores is what
      // matters, and near the top of the sample it is the rank.
      const double e = fit.e_value(scores[19]);
      EXPECT_GT(e, 20 / 2.0) << seed;
      EXPECT_LT(e, 20 * 2.0) << seed;
      EXPECT_NEAR(fit.score_at(fit.e_value(scores[5])), scores[5], 1e-9 * std::abs(scores[5]) + 1e-9);
      EXPECT_NEAR(fit.bit_score(scores[5]), std::log2(area / fit.e_value(scores[5])), 1e-9);
      // 1000 spacings: the predictive E-value is the plug-in one, K area exp(-lambda s), within a few percent.
      const double plug_in = fit.k * area * std::exp(-fit.lambda * scores[5]);
      EXPECT_NEAR(fit.e_value(scores[5]), plug_in, 0.05 * plug_in) << seed;
    }
  }
}

// What an E-value threshold promises: the score a fit puts at E = 0.01 is reached by chance 0.01 times on
// average, over the samples the fit could have come from. From 45 chance alignments (35 spacings fitted) the
// plug-in threshold, with lambda's error multiplied by the extrapolation, lets in about twice that; the
// predictive one keeps the promise. Checked against the true law the samples are drawn from.
TEST(ScoreStatistics, AThresholdFromFewAlignmentsKeepsItsEValueOnAverage) {
  const double lambda = 0.5, k = 0.01, area = 1e5, e = 0.01;
  double predictive = 0, plug_in = 0;
  const int samples = 4000;
  for (int seed = 1; seed <= samples; ++seed) {
    const auto fit = fit_declumped_scores(poisson_scores(lambda, k, area, 45, static_cast<std::uint32_t>(seed)), area);
    ASSERT_TRUE(fit.valid()) << seed;
    ASSERT_EQ(fit.spacings, 35.0) << seed;
    ScoreStatistics exact = fit;
    exact.spacings = 0;
    const auto truth = [&](double score) { return k * area * std::exp(-lambda * score); };
    predictive += truth(fit.score_at(e)) / samples;
    plug_in += truth(exact.score_at(e)) / samples;
    EXPECT_NEAR(fit.e_value(fit.score_at(e)), e, 1e-9 * e);
    EXPECT_GT(fit.score_at(e), exact.score_at(e)) << seed;
  }
  EXPECT_NEAR(predictive, e, 0.25 * e) << "plug-in: " << plug_in;
  EXPECT_GT(plug_in, 1.5 * e) << "predictive: " << predictive;
}

// The predictive tail against a Monte Carlo average of the plug-in tail over lambda's posterior,
// Gamma(n, n / lambda-hat).
TEST(ScoreStatistics, ThePredictiveEValueIsThePlugInOneAveragedOverLambda) {
  ScoreStatistics s;
  s.lambda = 0.8;
  s.k = 0.02;
  s.area = 5e4;
  s.anchor_score = 3.0;
  s.spacings = 20;
  std::mt19937 rng(3);
  std::gamma_distribution<double> posterior(s.spacings, s.lambda / s.spacings);
  const int draws = 200000;
  for (double score : {4.0, 10.0, 16.0}) {
    double mean = 0;
    std::mt19937 same(rng);
    for (int d = 0; d < draws; ++d) {
      mean += s.k * s.area * std::exp(-s.lambda * s.anchor_score) *
              std::exp(-posterior(same) * (score - s.anchor_score)) / draws;
    }
    EXPECT_NEAR(s.e_value(score), mean, 0.02 * mean) << score;
  }
  // At and below the anchor the fit's count itself.
  EXPECT_DOUBLE_EQ(s.e_value(2.0), s.k * s.area * std::exp(-s.lambda * 2.0));
  EXPECT_NEAR(s.score_at(s.e_value(12.0)), 12.0, 1e-9);
  EXPECT_NEAR(s.score_at(s.e_value(1.0)), 1.0, 1e-9);
}

TEST(ScoreStatistics, RealAlignmentsAtTheTopAreSetAsideAndFarBelowOneChanceHit) {
  const double lambda = 0.8, k = 0.1, area = 2e5;
  auto scores = poisson_scores(lambda, k, area, 300, 7);
  // 25 revisits far above chance: more than first_rank, so only the refit sets them aside.
  std::vector<double> with_real;
  for (int r = 0; r < 25; ++r) with_real.push_back(scores.front() + 60.0 - r);
  with_real.insert(with_real.end(), scores.begin(), scores.end());
  const auto fit = fit_declumped_scores(with_real, area);
  ASSERT_TRUE(fit.valid());
  EXPECT_NEAR(fit.lambda, mean_excess_rate(scores), 0.1 * lambda) << "as if the real ones were not there";
  EXPECT_GE(fit.first_fitted_rank, 26U);
  EXPECT_LT(fit.e_value(with_real[24]), 1e-6);
  EXPECT_GT(fit.e_value(scores[40]), 1.0);
}

TEST(ScoreStatistics, TooFewOrFlatScoresGiveNoFit) {
  EXPECT_FALSE(fit_declumped_scores(std::vector<double>(10, 1.0), 1e4).valid());
  EXPECT_FALSE(fit_declumped_scores(std::vector<double>(200, 3.0), 1e4).valid()) << "scores that do not fall";
  EXPECT_FALSE(fit_declumped_scores(poisson_scores(1, 1, 1e4, 200, 1), 0).valid());
  EXPECT_FALSE(ScoreStatistics{}.valid());
}

TEST(ScoreStatistics, TheSearchAreaCountsTheCellsTheEngineVisits) {
  for (std::size_t n : {1, 5, 37}) {
    for (std::size_t sep : {0, 1, 4, 40}) {
      std::size_t cells = 0;
      for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j < n; ++j) cells += i >= j + std::max<std::size_t>(sep, 1) ? 1 : 0;
      }
      EXPECT_DOUBLE_EQ(search_area(n, n, true, sep, false), static_cast<double>(cells)) << n << " " << sep;
      EXPECT_DOUBLE_EQ(search_area(n, n, true, sep, true), 2.0 * static_cast<double>(cells)) << n << " " << sep;
    }
  }
  EXPECT_DOUBLE_EQ(search_area(4, 7, false, 0, false), 28.0);
}

TEST(ScoreStatistics, ThePathScoreSumsThePairsAndChargesTheSkippedImages) {
  // Scores s(i, j) = i + 10 j on a 6 x 6 grid; pairs (1,0) (2,1) (4,2) (5,4): A skips 3, B skips 3.
  std::vector<float> values(36);
  for (std::size_t i = 0; i < 6; ++i) {
    for (std::size_t j = 0; j < 6; ++j) values[i * 6 + j] = static_cast<float>(i + 10 * j);
  }
  align::LocalAlignment a;
  a.pairs = {{1, 0}, {2, 1}, {4, 2}, {5, 4}};
  const double expected = (1 + 0) + (2 + 10) + (4 + 20) + (5 + 40) - 1.5 - 2.0;
  EXPECT_DOUBLE_EQ(align::path_score(a, align::ScoreSource::dense(values, 6, 6), 1.5, 2.0), expected);
}

}  // namespace
}  // namespace seqtopo::significance
