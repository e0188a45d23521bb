#pragma once
// NumPy .npy files (format versions 1-3). Read: float16/32/64, signed and unsigned integers of 1 to 8 bytes
// and booleans, either byte order, C or Fortran order (numpy.load reads them all, and deep descriptors are
// often saved as float16 or quantized to uint8), converted to float or double. Other dtypes (complex,
// strings, records), NaN/Inf values and shapes of the wrong rank are rejected with an InputError naming the
// file. Written: little-endian float32 / float64, C order.
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "seqtopo/core/dense_matrix.hpp"

namespace seqtopo::io {

struct NpyHeader {
  std::string dtype;     // the header's descr, e.g. "<f4", ">f8", "|u1", "<f2"
  char kind = 'f';       // 'f' float, 'i' signed integer, 'u' unsigned integer, 'b' boolean
  std::size_t item = 4;  // bytes per value
  bool big_endian = false;
  bool fortran_order = false;
  std::vector<std::size_t> shape;
  std::size_t data_offset = 0;  // bytes from the start of the file to the data
};

NpyHeader read_npy_header(const std::filesystem::path& path);

// A 2-D array, converted to T. Values must be finite.
template <typename T>
DenseMatrix<T> read_npy_matrix(const std::filesystem::path& path);

// Writes a 2-D float32 / float64 array (version 1.0), atomically.
template <typename T>
void write_npy(const std::filesystem::path& path, const DenseMatrix<T>& matrix);
// The same bytes, for callers that stage files themselves.
template <typename T>
std::string encode_npy(const DenseMatrix<T>& matrix);
// encode_npy() in two parts, the header and the values as they are in memory (a view of `matrix`), for writing
// a large matrix without a copy.
template <typename T>
std::string npy_header(const DenseMatrix<T>& matrix);
template <typename T>
std::string_view npy_body(const DenseMatrix<T>& matrix);

}  // namespace seqtopo::io
