#pragma once
// A matrix drawn as a picture (mapping paper Fig. 2): brighter = more similar, with polylines drawn
// over it (e.g. alignments: kept in one colour, pruned in another).
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "seqtopo/core/dense_matrix.hpp"
#include "seqtopo/core/rgb_image.hpp"
#include "seqtopo/plot/legend.hpp"

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

// The values drawn black and white: the 1st and 99th percentiles (robust) or the minimum and maximum of the
// finite values. A matrix of more than kDisplayRangeSample values has the percentiles of a deterministic sample:
// every s-th value in row-major order, s = ceil(size / kDisplayRangeSample) raised to the first stride coprime
// to the number of columns (so that every column is sampled). Smaller matrices use every value.
struct ValueRange {
  float lo = 0, hi = 1;
};
inline constexpr std::size_t kDisplayRangeSample = std::size_t{1} << 20U;
ValueRange display_range(const DenseMatrix<float>& matrix, bool robust = true);

// A grey-level PNG (one channel) of the matrix alone, one pixel per cell up to max_size (block means above),
// `range` mapped to black..white: the layer the interactive report zooms into.
std::string matrix_grey_png(const DenseMatrix<float>& matrix, ValueRange range, int max_size = 2048);
// The same as a grey-level JPEG (quality 90): a quarter of the bytes for large noisy matrices.
std::string matrix_grey_jpeg(const DenseMatrix<float>& matrix, ValueRange range, int max_size = 2048);

// matrix_image() as a figure for a paper: index axes with ticks (left: rows, below: columns), a colour bar
// of the grey levels with its values, a title and a legend of the overlays.
struct MatrixFigureConfig {
  std::string title;
  std::string row_label = "image i", column_label = "image j";
  std::string value_label = "similarity";
  std::vector<LegendEntry> legend;
  // A drawn cell stands for block x block indices (an overview of a larger matrix, plot/matrix_overview.hpp);
  // rows / cols: the indices the axes span (0 = the matrix's rows and cols times block).
  std::size_t block = 1, rows = 0, cols = 0;
  MatrixImageConfig image;
};
RgbImage matrix_figure(const DenseMatrix<float>& matrix, const std::vector<Polyline>& overlays = {},
                       const MatrixFigureConfig& config = {});

}  // namespace seqtopo::plot
