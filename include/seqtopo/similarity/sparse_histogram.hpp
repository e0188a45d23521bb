#pragma once
// A histogram that stores only its non-empty bins. The joint histogram of the mapping paper has 20,480 bins
// but an image fills only a few hundred to a few thousand of them, so comparing the stored bins is an order
// of magnitude less work than comparing dense arrays.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace seqtopo::similarity {

struct SparseHistogram {
  std::uint32_t dimension = 0;      // number of bins of the dense histogram
  std::vector<std::uint32_t> bins;  // indices of the non-empty bins, strictly increasing, < dimension
  std::vector<float> values;        // their values (> 0), same length as bins

  std::size_t nonzeros() const { return bins.size(); }
  // Keeps the positive entries of a dense histogram. Throws std::invalid_argument on negative or
  // non-finite values (a histogram counts things).
  static SparseHistogram from_dense(std::span<const float> dense);
  std::vector<float> to_dense() const;
  // Throws std::invalid_argument unless the invariants above hold.
  void validate() const;

  friend bool operator==(const SparseHistogram&, const SparseHistogram&) = default;
};

}  // namespace seqtopo::similarity
