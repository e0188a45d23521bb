#include "seqtopo/similarity/contrast_enhancement.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace seqtopo::similarity {

float contrast_score(float v, double sum, double sum2, double count) {
  const double mean = sum / count;
  const double sd = std::sqrt(std::max(0.0, sum2 / count - mean * mean));
  return static_cast<float>((v - mean) / std::max(sd, 1e-9));
}

// Term by term over all cells: each cell's sums still run over t in order (no fused multiply-add,
// -ffp-contract=off), while the loop over b vectorises.
[[gnu::target_clones("avx2", "default")]] void window_sums(double* sum, double* sum2, const float* first,
                                                           std::size_t stride, std::size_t terms, std::size_t count) {
  std::fill(sum, sum + count, 0.0);
  std::fill(sum2, sum2 + count, 0.0);
  for (std::size_t t = 0; t < terms; ++t) {
    const float* v = first + t * stride;
    for (std::size_t b = 0; b < count; ++b) {
      const double x = v[b];
      sum[b] += x;
      sum2[b] += x * x;
    }
  }
}

void enhance_row(const float* row, std::size_t cols, std::size_t window, float* out) {
  const std::size_t w = std::min(window, cols);  // a wider window is the whole row
  std::vector<double> sum(cols), sum2(cols);
  // Cells whose window is not clipped (c in [w, cols - w)) have windows of 2w + 1 cells starting one apart:
  // one call sums them all. The clipped cells at both ends take one call each.
  std::size_t in_lo = w, in_hi = cols > w ? cols - w : 0;
  if (in_hi > in_lo) {
    window_sums(sum.data() + in_lo, sum2.data() + in_lo, row + (in_lo - w), 1, 2 * w + 1, in_hi - in_lo);
  } else {
    in_lo = in_hi = 0;
  }
  for (std::size_t c = 0; c < cols; ++c) {
    const std::size_t lo = c > w ? c - w : 0, hi = std::min(cols, c + w + 1);
    if (c < in_lo || c >= in_hi) window_sums(&sum[c], &sum2[c], row + lo, 1, hi - lo, 1);
    out[c] = contrast_score(row[c], sum[c], sum2[c], static_cast<double>(hi - lo));
  }
}

SimilarityMatrix enhance_contrast(const SimilarityMatrix& s, std::size_t window) {
  if (window == 0) return s;
  SimilarityMatrix out(s.rows, s.cols);
  // Each row is independent and summed in a fixed order: identical results for any thread count.
#pragma omp parallel for schedule(static)
  for (long r = 0; r < static_cast<long>(s.rows); ++r) {
    const auto i = static_cast<std::size_t>(r);
    enhance_row(s.row(i).data(), s.cols, window, out.row(i).data());
  }
  return out;
}

SimilarityMatrix enhance_contrast_symmetric(const SimilarityMatrix& s, std::size_t window, float offset) {
  if (!s.square()) throw std::invalid_argument("symmetric contrast enhancement needs a square matrix");
  const SimilarityMatrix e = enhance_contrast(s, window);
  SimilarityMatrix out(s.rows, s.cols);
  for (std::size_t i = 0; i < s.rows; ++i) {
    for (std::size_t j = 0; j < s.cols; ++j) out(i, j) = 0.5F * (e(i, j) + e(j, i)) - offset;
  }
  return out;
}

}  // namespace seqtopo::similarity
