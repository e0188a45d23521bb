#pragma once
// An overview of a score matrix too large to hold (N x N at N = 10^5 is 40 GB): at most max_side x
// max_side cells, each the maximum of its block of block x block scores, read from a score source row
// by row, so only one row and the overview are ever in memory. The maximum, not the mean, keeps a
// revisit one cell wide visible at any reduction. Draw it with matrix_image(), dividing matrix
// coordinates by `block` (overview_coordinate()).
//
//   const auto overview = plot::matrix_overview(streamed.source(), {.symmetric = true});
//   // 100,000 x 100,000 scores -> 2000 x 2000 cells, block 50
#include <cstddef>

#include "seqtopo/align/score_source.hpp"
#include "seqtopo/core/dense_matrix.hpp"

namespace seqtopo::plot {

struct OverviewConfig {
  std::size_t max_side = 2048;  // [overview cells] larger side of the result
  // The source is symmetric (score(i, j) == score(j, i)): only j <= i is read, half the reads, and the
  // upper triangle is mirrored. The result is the same as for a full read.
  bool symmetric = false;
};

struct MatrixOverview {
  DenseMatrix<float> cells;  // ceil(rows / block) x ceil(cols / block)
  std::size_t block = 1;     // [scores per overview cell, per side]: the smallest with both sides <= max_side
};

// Throws std::invalid_argument for max_side = 0 or a symmetric source that is not square. NaN scores are
// skipped (a block of NaN only is -infinity).
MatrixOverview matrix_overview(const align::ScoreSource& scores, const OverviewConfig& config = {});

// The same overview of a matrix in memory (a figure of a large dense matrix: block maxima, as for a streamed one).
// max_side = 0 throws std::invalid_argument.
MatrixOverview matrix_overview(const DenseMatrix<float>& scores, std::size_t max_side = 2048);

// Where matrix position x (a row or column, in score cells) falls in the overview, in overview cells,
// such that matrix_image() draws it at the centre of the overview cell that holds it.
double overview_coordinate(double x, std::size_t block);

}  // namespace seqtopo::plot
