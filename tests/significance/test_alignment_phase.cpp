#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

#include "seqtopo/significance/alignment_phase.hpp"

namespace seqtopo::significance {
namespace {

// Every global path from (0, 0) to (n, n) by diagonal steps (scoring the cell) and gaps, best score.
double brute_force(const std::vector<float>& cells, std::size_t n, float gap, std::size_t i, std::size_t j) {
  if (i == n && j == n) return 0;
  double best = -std::numeric_limits<double>::infinity();
  if (i < n && j < n) best = std::max(best, cells[i * n + j] + brute_force(cells, n, gap, i + 1, j + 1));
  if (i < n) best = std::max(best, -gap + brute_force(cells, n, gap, i + 1, j));
  if (j < n) best = std::max(best, -gap + brute_force(cells, n, gap, i, j + 1));
  return best;
}

std::vector<float> gaussian(std::size_t count, float offset, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> normal;
  std::vector<float> v(count);
  for (auto& x : v) x = normal(rng) - offset;
  return v;
}

// Best local alignment score of an n x n table of i.i.d. draws (textbook Smith-Waterman with linear gaps).
double best_local(const std::vector<float>& pool, std::size_t n, float gap, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<double> row(n + 1, 0.0), next(n + 1, 0.0);
  double best = 0;
  for (std::size_t i = 1; i <= n; ++i) {
    next[0] = 0;
    for (std::size_t j = 1; j <= n; ++j) {
      const float s = pool[rng() % pool.size()];
      next[j] = std::max({0.0, row[j - 1] + s, row[j] - gap, next[j - 1] - gap});
      best = std::max(best, next[j]);
    }
    std::swap(row, next);
  }
  return best;
}

TEST(AlignmentPhase, TheGlobalRateIsTheBestPathOverN) {
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    const std::size_t n = 1 + seed % 4;
    const std::vector<float> cells = gaussian(n * n, 0.3F, seed);
    for (float gap : {0.5F, 1.5F}) {
      EXPECT_NEAR(global_alignment_rate(cells, n, gap), brute_force(cells, n, gap, 0, 0) / static_cast<double>(n),
                  1e-9);
    }
  }
  EXPECT_THROW(global_alignment_rate(std::vector<float>(3), 2, 1.0F), std::invalid_argument);
  EXPECT_THROW(resampled_global_rate({}, 8, 1.0F), std::invalid_argument);
}

// The sign of the rate is the phase (Arratia & Waterman): where it is positive the best local alignment of
// i.i.d. scores grows like the table's side, where it is clearly negative like its logarithm.
TEST(AlignmentPhase, ItsSignIsThePhaseOfLocalAlignment) {
  const float gap = 1.5F;
  const std::vector<float> low = gaussian(100000, 0.25F, 7), high = gaussian(100000, 1.0F, 7);
  EXPECT_GT(resampled_global_rate(low, 256, gap), 0.1);
  EXPECT_LT(resampled_global_rate(high, 256, gap), -0.3);
  EXPECT_EQ(resampled_global_rate(low, 64, gap, 3), resampled_global_rate(low, 64, gap, 3)) << "deterministic";
  double linear = 0, logarithmic = 0;
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    linear += best_local(low, 400, gap, seed) / best_local(low, 100, gap, seed + 10);
    logarithmic += best_local(high, 400, gap, seed) / best_local(high, 100, gap, seed + 10);
  }
  EXPECT_GT(linear / 3, 3.0) << "4 times the side: about 4 times the score";
  EXPECT_LT(logarithmic / 3, 2.0) << "4 times the side: about 1 + ln 4 / ln 100 times the score";
}

}  // namespace
}  // namespace seqtopo::significance
