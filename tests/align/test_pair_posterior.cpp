// Posterior decoding of alignment pairs against a brute-force sum over every chain of pairs on tiny matrices,
// and on planted matrices: a wrong pair inside a long correct alignment is less sure than its neighbours.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>

#include "seqtopo/align/pair_posterior.hpp"

namespace seqtopo::align {
namespace {

// Every chain (i1 < i2 < ..., j1 < j2 < ...) of a rows x cols matrix, its weight exp(lambda * score): the
// posterior of each cell is the weight of the chains through it over all chains and the empty one.
// With `skipped`, a chain also puts every row it skips between two pairs at the column of the pair before.
std::vector<double> brute_force(const std::vector<float>& s, std::size_t rows, std::size_t cols,
                                const PosteriorConfig& c, bool skipped = false) {
  std::vector<double> through(rows * cols, 0.0);
  double total = 1.0;  // the empty chain
  std::vector<std::pair<std::size_t, std::size_t>> chain;
  std::function<void(double)> extend = [&](double score) {
    const auto [pi, pj] = chain.back();
    const double w = std::exp(c.lambda * score);
    total += w;
    for (std::size_t k = 0; k < chain.size(); ++k) {
      const auto [i, j] = chain[k];
      through[i * cols + j] += w;
      if (skipped && k + 1 < chain.size()) {
        for (std::size_t r = i + 1; r < chain[k + 1].first; ++r) through[r * cols + j] += w;
      }
    }
    for (std::size_t i = pi + 1; i < rows; ++i) {
      for (std::size_t j = pj + 1; j < cols; ++j) {
        chain.emplace_back(i, j);
        extend(score + s[i * cols + j] - c.gap_a * static_cast<double>(i - pi - 1) -
               c.gap_b * static_cast<double>(j - pj - 1));
        chain.pop_back();
      }
    }
  };
  for (std::size_t i = 0; i < rows; ++i) {
    for (std::size_t j = 0; j < cols; ++j) {
      chain = {{i, j}};
      extend(s[i * cols + j]);
    }
  }
  for (auto& v : through) v /= total;
  return through;
}

TEST(PairPosterior, EqualsTheSumOverEveryChainOnTinyMatrices) {
  std::mt19937 rng(5);
  std::normal_distribution<float> noise(0.0F, 1.0F);
  for (int trial = 0; trial < 20; ++trial) {
    const std::size_t rows = 3 + trial % 3, cols = 3 + (trial / 3) % 3;
    std::vector<float> s(rows * cols);
    for (auto& v : s) v = noise(rng);
    PosteriorConfig c;
    c.lambda = 0.5 + 0.1 * trial;
    c.gap_a = 0.3 + 0.05 * trial;
    c.gap_b = 0.7;
    c.band = 8;  // wider than the matrix: every chain is inside
    // An alignment through every row (the band follows it); its pairs are the cells asked about.
    LocalAlignment a;
    for (std::size_t i = 0; i < rows; ++i) a.pairs.emplace_back(i, std::min(i, cols - 1));
    const auto expected = brute_force(s, rows, cols, c);
    const auto got = pair_posteriors(a, ScoreSource::dense(s, rows, cols), c);
    ASSERT_EQ(got.size(), a.pairs.size());
    for (std::size_t k = 0; k < got.size(); ++k) {
      const auto [i, j] = a.pairs[k];
      EXPECT_NEAR(got[k], expected[i * cols + j], 1e-9) << trial << " (" << i << ", " << j << ")";
    }
    // Within one column either side: the sum of the three cells' posteriors.
    c.tolerance = 1;
    const auto near = pair_posteriors(a, ScoreSource::dense(s, rows, cols), c);
    for (std::size_t k = 0; k < near.size(); ++k) {
      const auto [i, j] = a.pairs[k];
      double sum = 0;
      for (std::size_t jj = j == 0 ? 0 : j - 1; jj <= std::min(cols - 1, j + 1); ++jj) sum += expected[i * cols + jj];
      EXPECT_NEAR(near[k], std::min(1.0, sum), 1e-9) << trial << " (" << i << ", " << j << ")";
    }
  }
}

TEST(RowPosterior, EveryRowTakesItsMostProbableColumnAsTheBruteForceSumHasIt) {
  std::mt19937 rng(11);
  std::normal_distribution<float> noise(0.0F, 1.0F);
  for (int trial = 0; trial < 12; ++trial) {
    const std::size_t rows = 4 + trial % 2, cols = 4 + (trial / 2) % 2;
    std::vector<float> s(rows * cols);
    for (auto& v : s) v = noise(rng);
    PosteriorConfig c;
    c.lambda = 0.6 + 0.1 * trial;
    c.gap_a = c.gap_b = 0.5;
    c.band = 8;
    c.tolerance = trial % 2;
    // An alignment of one pair in the middle: the band reaches every row before and after it.
    LocalAlignment a;
    a.pairs = {{rows / 2, cols / 2}};
    const auto expected = brute_force(s, rows, cols, c, true);
    const auto got = row_posteriors(a, ScoreSource::dense(s, rows, cols), c);
    ASSERT_EQ(got.size(), rows) << trial;
    for (std::size_t i = 0; i < rows; ++i) {
      std::size_t best = 0;
      for (std::size_t j = 1; j < cols; ++j) {
        if (expected[i * cols + j] > expected[i * cols + best]) best = j;
      }
      double within = 0;
      for (std::size_t jj = best >= c.tolerance ? best - c.tolerance : 0; jj <= std::min(cols - 1, best + c.tolerance);
           ++jj)
        within += expected[i * cols + jj];
      EXPECT_EQ(got[i].row, i);
      EXPECT_EQ(got[i].col, best) << trial << " row " << i;
      EXPECT_NEAR(got[i].posterior, std::min(1.0, within), 1e-9) << trial << " row " << i;
    }
  }
}

TEST(RowPosterior, BeyondAnAlignmentsEndTheRowsFollowTheRevisitItStoppedShortOf) {
  // A revisit on the diagonal +5 of rows 0..39, weak (+0.4) in rows 30..39 where the alignment given ends at 29.
  const std::size_t n = 60;
  std::mt19937 rng(4);
  std::normal_distribution<float> noise(-1.0F, 0.7F);
  std::vector<float> s(n * n);
  for (auto& v : s) v = noise(rng);
  LocalAlignment a;
  for (std::size_t i = 0; i < 40; ++i) {
    s[i * n + i + 5] = i < 30 ? 2.5F : 0.4F;
    if (i < 30) a.pairs.emplace_back(i, i + 5);
  }
  PosteriorConfig c;
  c.band = 8;
  c.tolerance = 1;
  const auto rows = row_posteriors(a, ScoreSource::dense(s, n, n), c);
  ASSERT_EQ(rows.size(), 38U);  // rows 0..29 and 8 after
  for (const auto& r : rows) {
    if (r.row < 30) {
      EXPECT_EQ(r.col, r.row + 5) << r.row;
      EXPECT_GT(r.posterior, 0.9) << r.row;
    } else {
      EXPECT_NEAR(static_cast<double>(r.col), static_cast<double>(r.row + 5), 1.0) << r.row;
      EXPECT_LT(r.posterior, rows[20].posterior) << "less sure past the end";
    }
  }
}

// A tolerance wider than the matrix covers every column: 2^32 - 1 and 2^64 - 1 give what the matrix's width gives
// (the window is clipped to the band, so the cost does not grow with the value either; 2^64 - 1 once wrapped to
// a window of no column and a posterior of 0).
TEST(RowPosterior, AToleranceBeyondTheMatrixIsTheWholeRow) {
  const std::size_t n = 60;
  std::mt19937 rng(4);
  std::normal_distribution<float> noise(-1.0F, 0.7F);
  std::vector<float> s(n * n);
  for (auto& v : s) v = noise(rng);
  LocalAlignment a;
  for (std::size_t i = 0; i < 30; ++i) {
    s[i * n + i + 5] = 2.5F;
    a.pairs.emplace_back(i, i + 5);
  }
  PosteriorConfig c;
  c.band = 8;
  c.tolerance = n;
  const auto whole = row_posteriors(a, ScoreSource::dense(s, n, n), c);
  const auto pairs = pair_posteriors(a, ScoreSource::dense(s, n, n), c);
  for (const std::size_t tolerance : {std::size_t{4294967295U}, std::numeric_limits<std::size_t>::max()}) {
    c.tolerance = tolerance;
    const auto rows = row_posteriors(a, ScoreSource::dense(s, n, n), c);
    ASSERT_EQ(rows.size(), whole.size());
    for (std::size_t k = 0; k < rows.size(); ++k) {
      EXPECT_EQ(rows[k].col, whole[k].col);
      EXPECT_EQ(rows[k].posterior, whole[k].posterior) << tolerance << " row " << rows[k].row;
      if (rows[k].row < 30) {
        EXPECT_GT(rows[k].posterior, 0.5) << rows[k].row;
      }
    }
    EXPECT_EQ(pair_posteriors(a, ScoreSource::dense(s, n, n), c), pairs) << tolerance;
  }
}

TEST(PairPosterior, AReverseAlignmentIsTheForwardOneOnTheMirroredColumns) {
  std::mt19937 rng(9);
  std::normal_distribution<float> noise(0.0F, 1.0F);
  const std::size_t rows = 4, cols = 5;
  std::vector<float> s(rows * cols), mirrored(rows * cols);
  for (auto& v : s) v = noise(rng);
  for (std::size_t i = 0; i < rows; ++i) {
    for (std::size_t j = 0; j < cols; ++j) mirrored[i * cols + j] = s[i * cols + (cols - 1 - j)];
  }
  PosteriorConfig c;
  c.band = 8;
  LocalAlignment reverse;
  reverse.direction = Direction::reverse;
  for (std::size_t i = 0; i < rows; ++i) reverse.pairs.emplace_back(i, cols - 1 - i);
  LocalAlignment forward;
  for (std::size_t i = 0; i < rows; ++i) forward.pairs.emplace_back(i, i);
  const auto r = pair_posteriors(reverse, ScoreSource::dense(s, rows, cols), c);
  const auto f = pair_posteriors(forward, ScoreSource::dense(mirrored, rows, cols), c);
  ASSERT_EQ(r.size(), f.size());
  for (std::size_t k = 0; k < r.size(); ++k) EXPECT_NEAR(r[k], f[k], 1e-12) << k;
}

TEST(PairPosterior, AWrongPairInsideALongCorrectAlignmentIsLessSureThanItsNeighbours) {
  const std::size_t n = 120;
  std::mt19937 rng(2);
  std::normal_distribution<float> noise(-1.0F, 0.5F);
  std::vector<float> s(n * n);
  for (auto& v : s) v = noise(rng);
  // A revisit: rows 60..109 match columns 0..49 at +3; at row 85 the right partner looks unlike, and the image
  // beside it looks alike.
  LocalAlignment a;
  for (std::size_t k = 0; k < 50; ++k) {
    s[(60 + k) * n + k] = 3.0F;
    a.pairs.emplace_back(60 + k, k);
  }
  s[85 * n + 25] = -4.0F;
  s[85 * n + 26] = 2.5F;
  PosteriorConfig c;
  c.self = true;
  c.min_separation = 10;
  const auto p = pair_posteriors(a, ScoreSource::dense(s, n, n), c);
  for (std::size_t k = 5; k < 45; ++k) {
    if (k >= 24 && k <= 26) continue;
    EXPECT_GT(p[k], 0.95) << k;
  }
  EXPECT_LT(p[25], 0.5) << "the pair whose images look unlike";
  EXPECT_LT(p[25], p[20]);
  EXPECT_LT(p[25], p[30]);
}

TEST(PairPosterior, BadInputIsAnError) {
  std::vector<float> s(9, 1.0F);
  LocalAlignment a;
  a.pairs = {{0, 0}, {3, 1}};
  EXPECT_THROW(pair_posteriors(a, ScoreSource::dense(s, 3, 3), {}), std::invalid_argument);
  a.pairs = {{0, 0}};
  PosteriorConfig c;
  c.lambda = 0;
  EXPECT_THROW(pair_posteriors(a, ScoreSource::dense(s, 3, 3), c), std::invalid_argument);
  EXPECT_TRUE(pair_posteriors(LocalAlignment{}, ScoreSource::dense(s, 3, 3), {}).empty());
}

}  // namespace
}  // namespace seqtopo::align
