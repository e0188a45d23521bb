#include "seqtopo/similarity/hubness.hpp"

#include <algorithm>
#include <functional>
#include <stdexcept>
#include <string>

namespace seqtopo::similarity {

std::vector<float> neighbourhood_similarity(const SimilarityMatrix& s, std::size_t k, std::size_t min_separation) {
  if (!s.square()) {
    throw std::invalid_argument("hubness correction needs a square matrix, got " + std::to_string(s.rows) + " x " +
                                std::to_string(s.cols));
  }
  const std::size_t n = s.rows;
  std::vector<float> r(n, 0.0F);
  if (k == 0) return r;
#pragma omp parallel
  {
    std::vector<float> far;
    far.reserve(n);
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      far.clear();
      const auto row = s.row(i);
      for (std::size_t j = 0; j < n; ++j) {
        if ((i > j ? i - j : j - i) >= min_separation) far.push_back(row[j]);
      }
      if (far.empty()) continue;
      const std::size_t m = std::min(k, far.size());
      std::nth_element(far.begin(), far.begin() + static_cast<std::ptrdiff_t>(m - 1), far.end(), std::greater<>());
      // The k highest, summed in a fixed order so the result does not depend on nth_element's arrangement.
      std::sort(far.begin(), far.begin() + static_cast<std::ptrdiff_t>(m), std::greater<>());
      double sum = 0;
      for (std::size_t t = 0; t < m; ++t) sum += far[t];
      r[i] = static_cast<float>(sum / static_cast<double>(m));
    }
  }
  return r;
}

void correct_hubness(SimilarityMatrix& s, std::size_t k, std::size_t min_separation) {
  if (k == 0) return;
  const std::vector<float> r = neighbourhood_similarity(s, k, min_separation);
  const std::size_t n = s.rows;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    float* row = s.values.data() + i * n;
    for (std::size_t j = 0; j < n; ++j) {
      row[j] = static_cast<float>(static_cast<double>(row[j]) - 0.5 * (static_cast<double>(r[i]) + r[j]));
    }
  }
}

}  // namespace seqtopo::similarity
