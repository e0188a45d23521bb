// The block-max overview against a brute-force block maximum, for full and symmetric reads and for a matrix in
// memory.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "seqtopo/plot/matrix_overview.hpp"

namespace seqtopo::plot {
namespace {

DenseMatrix<float> brute_force(const DenseMatrix<float>& m, std::size_t block) {
  DenseMatrix<float> out((m.rows + block - 1) / block, (m.cols + block - 1) / block,
                         -std::numeric_limits<float>::infinity());
  for (std::size_t i = 0; i < m.rows; ++i) {
    for (std::size_t j = 0; j < m.cols; ++j) out(i / block, j / block) = std::max(out(i / block, j / block), m(i, j));
  }
  return out;
}

DenseMatrix<float> random_matrix(std::size_t rows, std::size_t cols, unsigned seed, bool symmetric) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0F, 1.0F);
  DenseMatrix<float> m(rows, cols);
  for (auto& v : m.values) v = noise(rng);
  if (symmetric) {
    for (std::size_t i = 0; i < rows; ++i) {
      for (std::size_t j = 0; j < i; ++j) m(j, i) = m(i, j);
    }
  }
  return m;
}

TEST(MatrixOverview, EqualsBruteForceBlockMax) {
  struct Case {
    std::size_t rows, cols, max_side, block;
  };
  // block = the smallest with both sides <= max_side; uneven last blocks included
  const Case cases[] = {{1, 1, 4, 1},   {7, 7, 7, 1},   {7, 7, 6, 2},       {23, 23, 5, 5},
                        {50, 31, 8, 7}, {31, 50, 8, 7}, {100, 100, 10, 10}, {101, 101, 10, 11}};
  for (const Case& c : cases) {
    const auto m = random_matrix(c.rows, c.cols, static_cast<unsigned>(c.rows * 100 + c.cols), false);
    const auto overview =
        matrix_overview(align::ScoreSource::dense(m.values, c.rows, c.cols), {.max_side = c.max_side});
    EXPECT_EQ(overview.block, c.block) << c.rows << " x " << c.cols;
    const auto expected = brute_force(m, c.block);
    EXPECT_EQ(overview.cells.rows, expected.rows);
    EXPECT_EQ(overview.cells.cols, expected.cols);
    EXPECT_EQ(overview.cells.values, expected.values) << c.rows << " x " << c.cols << ", max side " << c.max_side;
  }
}

TEST(MatrixOverview, SymmetricReadsHalfAndGivesTheSameResult) {
  for (const std::size_t n : {1, 2, 9, 40, 97}) {
    for (const std::size_t max_side : {1, 3, 8, 200}) {
      const auto m = random_matrix(n, n, static_cast<unsigned>(n + max_side), true);
      std::atomic<std::size_t> reads{0};
      const align::ScoreSource source(n, n,
                                      [&](std::size_t i, std::size_t j_begin, std::size_t j_end, align::Score* out) {
                                        EXPECT_LE(j_end, i + 1) << "a symmetric overview reads only j <= i";
                                        reads += j_end - j_begin;
                                        for (std::size_t j = j_begin; j < j_end; ++j) out[j - j_begin] = m(i, j);
                                      });
      const auto overview = matrix_overview(source, {.max_side = max_side, .symmetric = true});
      EXPECT_EQ(reads.load(), n * (n + 1) / 2);
      const auto full = matrix_overview(align::ScoreSource::dense(m.values, n, n), {.max_side = max_side});
      EXPECT_EQ(overview.block, full.block);
      EXPECT_EQ(overview.cells.values, brute_force(m, full.block).values) << n << ", max side " << max_side;
    }
  }
}

TEST(MatrixOverview, SkipsNaNAndRefusesMisuse) {
  DenseMatrix<float> m(4, 4, 0.25F);
  m(0, 0) = std::numeric_limits<float>::quiet_NaN();
  m(0, 1) = -1.0F;
  const auto overview = matrix_overview(align::ScoreSource::dense(m.values, 4, 4), {.max_side = 2});
  EXPECT_EQ(overview.cells(0, 0), 0.25F);
  EXPECT_THROW(matrix_overview(align::ScoreSource::dense(m.values, 4, 4), {.max_side = 0}), std::invalid_argument);
  EXPECT_THROW(matrix_overview(align::ScoreSource::dense(m.values, 2, 8), {.symmetric = true}), std::invalid_argument);
}

// The overview of a matrix in memory (a large dense figure): the documented block and size, the same cells as a
// brute-force block maximum and as the score-source overview, NaN skipped.
TEST(MatrixOverview, DenseEqualsBruteForceBlockMax) {
  struct Case {
    std::size_t rows, cols, max_side, block;
  };
  const Case cases[] = {{1, 1, 4, 1},       {7, 7, 7, 1},      {7, 7, 6, 2},       {23, 23, 5, 5},
                        {50, 31, 8, 7},     {31, 50, 8, 7},    {101, 101, 10, 11}, {2049, 2049, 2048, 2},
                        {3600, 7, 2048, 2}, {4097, 3, 2048, 3}};
  for (const Case& c : cases) {
    auto m = random_matrix(c.rows, c.cols, static_cast<unsigned>(c.rows * 7 + c.cols), false);
    m.values[m.values.size() / 2] = std::numeric_limits<float>::quiet_NaN();
    const auto overview = matrix_overview(m, c.max_side);
    EXPECT_EQ(overview.block, c.block) << c.rows << " x " << c.cols;
    EXPECT_EQ(overview.cells.rows, (c.rows + c.block - 1) / c.block);
    EXPECT_EQ(overview.cells.cols, (c.cols + c.block - 1) / c.block);
    EXPECT_LE(std::max(overview.cells.rows, overview.cells.cols), c.max_side);
    EXPECT_EQ(overview.cells.values, brute_force(m, c.block).values) << c.rows << " x " << c.cols;
    EXPECT_EQ(
        overview.cells.values,
        matrix_overview(align::ScoreSource::dense(m.values, c.rows, c.cols), {.max_side = c.max_side}).cells.values);
  }
  // 3,600 images: 1800 x 1800 cells of 2 x 2 scores
  const DenseMatrix<float> nordland(3600, 3600, 0.5F);
  const auto overview = matrix_overview(nordland);
  EXPECT_EQ(overview.block, 2U);
  EXPECT_EQ(overview.cells.rows, 1800U);
  EXPECT_THROW(matrix_overview(nordland, 0), std::invalid_argument);
}

TEST(MatrixOverview, CoordinatesLandInTheCellThatHoldsThePosition) {
  EXPECT_EQ(overview_coordinate(17.0, 1), 17.0);  // no reduction: the matrix's own cells
  // matrix_image draws overview cell c at pixels [c, c + 1) times its scale; position x must fall in
  // overview cell floor(x / block).
  for (const std::size_t block : {2U, 5U, 50U}) {
    for (double x = 0; x < 500; ++x) {
      const double drawn = overview_coordinate(x, block) + 0.5;  // matrix_image's cell-centre offset
      EXPECT_EQ(static_cast<std::size_t>(std::floor(drawn)), static_cast<std::size_t>(x) / block)
          << x << ", block " << block;
    }
  }
}

}  // namespace
}  // namespace seqtopo::plot
