#include "seqtopo/similarity/sparse_histogram.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace seqtopo::similarity {

SparseHistogram SparseHistogram::from_dense(std::span<const float> dense) {
  if (dense.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw std::invalid_argument("histogram has too many bins for a sparse histogram");
  }
  SparseHistogram h;
  h.dimension = static_cast<std::uint32_t>(dense.size());
  for (std::size_t k = 0; k < dense.size(); ++k) {
    const float v = dense[k];
    if (!(v >= 0.0F) || !std::isfinite(v)) {
      throw std::invalid_argument("histogram bin " + std::to_string(k) + " is negative or not finite");
    }
    if (v > 0.0F) {
      h.bins.push_back(static_cast<std::uint32_t>(k));
      h.values.push_back(v);
    }
  }
  return h;
}

std::vector<float> SparseHistogram::to_dense() const {
  std::vector<float> dense(dimension, 0.0F);
  for (std::size_t k = 0; k < bins.size(); ++k) dense[bins[k]] = values[k];
  return dense;
}

void SparseHistogram::validate() const {
  if (bins.size() != values.size()) throw std::invalid_argument("sparse histogram: bins and values differ in length");
  for (std::size_t k = 0; k < bins.size(); ++k) {
    if (bins[k] >= dimension) throw std::invalid_argument("sparse histogram: bin index beyond the dimension");
    if (k > 0 && bins[k] <= bins[k - 1]) throw std::invalid_argument("sparse histogram: bins not strictly increasing");
    if (!(values[k] > 0.0F) || !std::isfinite(values[k])) {
      throw std::invalid_argument("sparse histogram: stored values must be positive and finite");
    }
  }
}

}  // namespace seqtopo::similarity
