#include "seqtopo/similarity/contrast_enhancement.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace seqtopo::similarity {

SimilarityMatrix enhance_contrast(const SimilarityMatrix& s, std::size_t window) {
  if (window == 0) return s;
  SimilarityMatrix out(s.rows, s.cols);
  // Each row is independent and summed in a fixed order: identical results for any thread count.
#pragma omp parallel for schedule(static)
  for (long r = 0; r < static_cast<long>(s.rows); ++r) {
    const auto row = s.row(static_cast<std::size_t>(r));
    for (std::size_t c = 0; c < s.cols; ++c) {
      const std::size_t lo = c > window ? c - window : 0;
      const std::size_t hi = std::min(s.cols, c + window + 1);
      double sum = 0, sum2 = 0;
      for (std::size_t k = lo; k < hi; ++k) {
        sum += row[k];
        sum2 += static_cast<double>(row[k]) * row[k];
      }
      const double n = static_cast<double>(hi - lo);
      const double mean = sum / n;
      const double sd = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
      out(static_cast<std::size_t>(r), c) = static_cast<float>((row[c] - mean) / std::max(sd, 1e-9));
    }
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
