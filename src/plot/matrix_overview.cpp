#include "seqtopo/plot/matrix_overview.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace seqtopo::plot {

MatrixOverview matrix_overview(const align::ScoreSource& scores, const OverviewConfig& config) {
  if (config.max_side == 0) throw std::invalid_argument("overview max_side must be at least 1");
  const std::size_t rows = scores.rows(), cols = scores.cols();
  if (config.symmetric && rows != cols) {
    throw std::invalid_argument("a symmetric overview needs a square source, got " + std::to_string(rows) + " x " +
                                std::to_string(cols));
  }
  MatrixOverview overview;
  const std::size_t larger = std::max(rows, cols);
  overview.block = std::max<std::size_t>(1, (larger + config.max_side - 1) / config.max_side);
  const std::size_t b = overview.block;
  overview.cells = DenseMatrix<float>((rows + b - 1) / b, (cols + b - 1) / b, -std::numeric_limits<float>::infinity());
  std::vector<float> row(cols);
  for (std::size_t i = 0; i < rows; ++i) {
    // Symmetric: for a block left of the diagonal every cell has j < i, and a diagonal block holds (j, i)
    // beside (i, j), so the lower triangle j <= i sees every value of every block at or below the diagonal.
    const std::size_t end = config.symmetric ? i + 1 : cols;
    scores.read_row(i, 0, end, row.data());
    float* out = overview.cells.values.data() + (i / b) * overview.cells.cols;
    for (std::size_t j = 0; j < end; ++j) {
      float& cell = out[j / b];
      if (row[j] > cell) cell = row[j];  // false for NaN: skipped
    }
  }
  if (config.symmetric) {
    for (std::size_t r = 0; r < overview.cells.rows; ++r) {
      for (std::size_t c = r + 1; c < overview.cells.cols; ++c) overview.cells(r, c) = overview.cells(c, r);
    }
  }
  return overview;
}

MatrixOverview matrix_overview(const DenseMatrix<float>& scores, std::size_t max_side) {
  if (max_side == 0) throw std::invalid_argument("overview max_side must be at least 1");
  MatrixOverview overview;
  const std::size_t rows = scores.rows, cols = scores.cols;
  overview.block = std::max<std::size_t>(1, (std::max(rows, cols) + max_side - 1) / max_side);
  const std::size_t b = overview.block;
  overview.cells = DenseMatrix<float>((rows + b - 1) / b, (cols + b - 1) / b, -std::numeric_limits<float>::infinity());
  for (std::size_t i = 0; i < rows; ++i) {
    const float* row = scores.values.data() + i * cols;
    float* out = overview.cells.values.data() + (i / b) * overview.cells.cols;
    for (std::size_t c = 0, j = 0; c < overview.cells.cols; ++c) {
      float cell = out[c];
      for (const std::size_t end = std::min(cols, j + b); j < end; ++j) {
        if (row[j] > cell) cell = row[j];  // false for NaN: skipped
      }
      out[c] = cell;
    }
  }
  return overview;
}

double overview_coordinate(double x, std::size_t block) {
  // matrix_image() draws cell c at (c + 0.5) pixels per cell; cell x of the matrix covers
  // [x, x + 1) / block in overview cells, whose centre is (x + 0.5) / block.
  return (x + 0.5) / static_cast<double>(block) - 0.5;
}

}  // namespace seqtopo::plot
