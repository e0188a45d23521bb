#pragma once
// A matrix drawn as a picture (mapping paper Fig. 2): brighter = more similar, with polylines drawn
// over it (e.g. alignments: kept in one colour, pruned in another).
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "seqtopo/core/dense_matrix.hpp"
#include "seqtopo/core/rgb_image.hpp"

namespace seqtopo::plot {

struct Polyline {
  std::vector<std::pair<double, double>> points;  // (row, column) in matrix cells
  std::array<std::uint8_t, 3> rgb{255, 0, 0};
  int thickness = 1;  // [pixels]
};

struct MatrixImageConfig {
  int min_size = 512;        // the image is upscaled (nearest cell) until its larger side is at least this [pixels]
  int max_size = 2048;       // and reduced (block means) when larger [pixels]
  bool robust_range = true;  // map the 1st..99th percentile to black..white instead of min..max
};

// Grey levels from the matrix values. Matrices larger than max_size are reduced by taking the mean of
// each block of cells, so isolated bright pixels may fade but diagonals stay visible.
RgbImage matrix_image(const DenseMatrix<float>& matrix, const std::vector<Polyline>& overlays = {},
                      const MatrixImageConfig& config = {});

}  // namespace seqtopo::plot
