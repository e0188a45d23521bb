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
      EXPECT_NEAR(fit.bit_score(scores[5]), (fit.lambda * scores[5] - std::log(fit.k)) / std::log(2.0), 1e-9);
    }
  }
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
  EXPECT_DOUBLE_EQ(path_score(a, align::ScoreSource::dense(values, 6, 6), 1.5, 2.0), expected);
}

}  // namespace
}  // namespace seqtopo::significance
