#pragma once
// All pairwise distances of one sequence (N x N, symmetric) or between two sequences (N x M).
//
// The symmetric case computes only the lower triangle and mirrors it; the diagonal is exactly 0. Work is
// split into square tiles of `tile` x `tile` cells so that the descriptors of one tile stay in cache while
// it is filled, and tiles are shared among threads. Every cell is computed by exactly one thread from its two
// descriptors alone, with a fixed order of summation, so the matrix is bit-identical for any thread count.
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "seqtopo/core/dense_matrix.hpp"
#include "seqtopo/similarity/distance.hpp"
#include "seqtopo/similarity/sparse_histogram.hpp"

namespace seqtopo::similarity {

// The descriptors of one sequence: either dense rows (thumbnails, external descriptors) or sparse histograms.
struct DescriptorSet {
  DenseMatrix<float> dense;             // one row per item; used when `sparse` is empty
  std::vector<SparseHistogram> sparse;  // one histogram per item

  static DescriptorSet from_dense(DenseMatrix<float> rows);
  static DescriptorSet from_sparse(std::vector<SparseHistogram> histograms);
  bool is_sparse() const { return !sparse.empty(); }
  std::size_t size() const { return is_sparse() ? sparse.size() : dense.rows; }
  std::size_t dimension() const;
  std::size_t memory_bytes() const;
};

struct MatrixConfig {
  unsigned threads = 0;   // 0 = every core
  std::size_t tile = 64;  // tile side [cells]
  // Called after each finished tile with (cells done, cells total), from one thread at a time.
  std::function<void(std::size_t, std::size_t)> progress = {};
  // The bytes the matrix may take: a larger one is refused (MemoryError) before it is allocated; unset: no check.
  std::optional<std::size_t> memory_budget = {};
};

// N x N distances of one sequence. Throws std::invalid_argument when the metric does not apply (chi2 on
// negative values) and MemoryError when the matrix would not fit in config.memory_budget.
DenseMatrix<float> distance_matrix(const DescriptorSet& items, Distance metric, const MatrixConfig& config = {});
// N x M distances: rows = a, columns = b. Both sets must be of the same kind and dimension.
DenseMatrix<float> distance_matrix(const DescriptorSet& a, const DescriptorSet& b, Distance metric,
                                   const MatrixConfig& config = {});

}  // namespace seqtopo::similarity
