#include "arrays.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace seqtopo::python {

MatrixView matrix_view(const py::handle& object, const char* name) {
  // ensure() returns the array itself when it is already float32 and C-contiguous (NumPy's
  // PyArray_FromAny hands back the same object), else a converted copy.
  auto array = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(object);
  if (!array) {
    PyErr_Clear();
    throw std::invalid_argument(std::string(name) + ": expected a 2-D array of numbers");
  }
  if (array.ndim() != 2) {
    throw std::invalid_argument(std::string(name) + ": expected a 2-D array, got " + std::to_string(array.ndim()) +
                                "-D");
  }
  MatrixView view;
  view.rows = static_cast<std::size_t>(array.shape(0));
  view.cols = static_cast<std::size_t>(array.shape(1));
  view.data = array.data();
  view.array = std::move(array);
  return view;
}

void require_finite(const MatrixView& view, const char* name) {
  for (std::size_t k = 0; k < view.size(); ++k) {
    if (!std::isfinite(view.data[k])) {
      throw std::invalid_argument(std::string(name) + ": non-finite value at row " + std::to_string(k / view.cols) +
                                  ", column " + std::to_string(k % view.cols));
    }
  }
}

SimilarityMatrix to_matrix(const MatrixView& view) {
  return SimilarityMatrix(view.rows, view.cols, std::vector<float>(view.data, view.data + view.size()));
}

py::array_t<std::int64_t> pairs_array(const std::vector<std::pair<std::size_t, std::size_t>>& pairs) {
  std::vector<std::int64_t> flat;
  flat.reserve(2 * pairs.size());
  for (const auto& [i, j] : pairs) {
    flat.push_back(static_cast<std::int64_t>(i));
    flat.push_back(static_cast<std::int64_t>(j));
  }
  return to_array(std::move(flat), {static_cast<py::ssize_t>(pairs.size()), 2});
}

}  // namespace seqtopo::python
