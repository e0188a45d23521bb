#pragma once
// NumPy arrays in and out of the library's matrices and vectors.
//
// In: a 2-D array is read as float32 in C order. An array that already is float32 and C-contiguous is
// used in place (its buffer is what the engine reads); anything else (float64, a strided view, a
// nested list) is converted once by NumPy.
// Out: results are moved from the library's std::vector into a NumPy array that owns it (through a
// capsule), so no result is copied on the way out.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "seqtopo/core/dense_matrix.hpp"

namespace seqtopo::python {

namespace py = pybind11;

// A read-only float32 row-major view of a 2-D array; `array` keeps the buffer alive.
struct MatrixView {
  py::array_t<float, py::array::c_style | py::array::forcecast> array;
  const float* data = nullptr;
  std::size_t rows = 0, cols = 0;

  std::size_t size() const { return rows * cols; }
};

// Throws std::invalid_argument ("<name>: expected a 2-D array, got ...") unless `object` is 2-D.
MatrixView matrix_view(const py::handle& object, const char* name);

// Throws std::invalid_argument ("<name>: non-finite value at row i, column j") on NaN or infinity.
// Reads only the buffer, so it may run without the GIL.
void require_finite(const MatrixView& view, const char* name);

// The view's values in a matrix the library owns (one copy).
SimilarityMatrix to_matrix(const MatrixView& view);

template <typename T>
py::array_t<T> to_array(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
  auto* owner = new std::vector<T>(std::move(values));
  const py::capsule release(owner, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(std::move(shape), owner->data(), release);
}

template <typename T>
py::array_t<T> to_array(std::vector<T>&& values) {
  const auto n = static_cast<py::ssize_t>(values.size());
  return to_array(std::move(values), {n});
}

inline py::array_t<float> to_array(SimilarityMatrix&& matrix) {
  const auto rows = static_cast<py::ssize_t>(matrix.rows), cols = static_cast<py::ssize_t>(matrix.cols);
  return to_array(std::move(matrix.values), {rows, cols});
}

// Index pairs as an (n, 2) int64 array.
py::array_t<std::int64_t> pairs_array(const std::vector<std::pair<std::size_t, std::size_t>>& pairs);

}  // namespace seqtopo::python
