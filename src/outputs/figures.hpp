#pragma once
// How the static figures are framed (titles, axis labels, legends), shared by the files and the reports.
#include "seqtopo/pipeline/localize_pipeline.hpp"
#include "seqtopo/pipeline/map_pipeline.hpp"
#include "seqtopo/plot/matrix_image.hpp"

namespace seqtopo::outputs {

// The matrix that similarity.png and the report's matrix view of `seqtopo map` draw. A streamed run's overview;
// else the scores, or, when the matrix is larger than kMaxDrawnSide a side, their overview of block maxima
// (plot/matrix_overview.hpp): each cell the maximum of b x b scores, b = ceil(N / kMaxDrawnSide), so the drawn
// matrix is at most kMaxDrawnSide cells a side (1800 x 1800 for 3,600 images) and a revisit one cell wide stays
// visible. Holds a reference to `run`.
inline constexpr std::size_t kMaxDrawnSide = 2048;
class DrawnMatrix {
 public:
  explicit DrawnMatrix(const pipeline::MapRun& run);
  DrawnMatrix(const DrawnMatrix&) = delete;
  DrawnMatrix& operator=(const DrawnMatrix&) = delete;
  const DenseMatrix<float>& cells() const { return *cells_; }
  std::size_t block() const { return block_; }  // [scores per drawn cell, per side]

 private:
  plot::MatrixOverview own_;
  const DenseMatrix<float>* cells_ = nullptr;
  std::size_t block_ = 1;
};

// The marks of the map's errors against the ground truth, in similarity.png and the report.
inline constexpr std::array<std::uint8_t, 3> kFalsePositiveColour{255, 0, 255}, kMissedColour{255, 200, 0};

// similarity.png of `seqtopo map` drawn from cells of `block` x `block` scores: what was aligned, its axes, the
// colour bar's meaning, the overlays' legend.
plot::MatrixFigureConfig map_similarity_figure(const pipeline::MapRun& run, std::size_t block);
// similarity.png of `seqtopo localize`: query frames (rows) x map frames (columns).
plot::MatrixFigureConfig localize_similarity_figure(const pipeline::LocalizeRun& run);

}  // namespace seqtopo::outputs
