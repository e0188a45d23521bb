#pragma once
// A plain row-major matrix: the currency between layers (similarity matrices, descriptors, scores).
#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "seqtopo/core/huge_pages.hpp"

namespace seqtopo {

template <typename T>
struct DenseMatrix {
  std::size_t rows = 0;
  std::size_t cols = 0;
  std::vector<T> values;  // rows * cols, row-major

  DenseMatrix() = default;
  // A large matrix asks for huge pages before its values are first written (core/huge_pages.hpp).
  DenseMatrix(std::size_t r, std::size_t c, T fill = T{}) : rows(r), cols(c) {
    values.reserve(r * c);
    advise_huge_pages(values.data(), r * c * sizeof(T));
    values.assign(r * c, fill);
  }
  DenseMatrix(std::size_t r, std::size_t c, std::vector<T> v) : rows(r), cols(c), values(std::move(v)) {
    if (values.size() != rows * cols) {
      throw std::invalid_argument("matrix data has " + std::to_string(values.size()) + " values, expected " +
                                  std::to_string(rows) + " x " + std::to_string(cols));
    }
  }

  T& operator()(std::size_t i, std::size_t j) { return values[i * cols + j]; }
  const T& operator()(std::size_t i, std::size_t j) const { return values[i * cols + j]; }
  std::span<T> row(std::size_t i) { return {values.data() + i * cols, cols}; }
  std::span<const T> row(std::size_t i) const { return {values.data() + i * cols, cols}; }
  bool empty() const { return rows == 0 || cols == 0; }
  bool square() const { return rows == cols; }

  friend bool operator==(const DenseMatrix&, const DenseMatrix&) = default;
};

using SimilarityMatrix = DenseMatrix<float>;

}  // namespace seqtopo
