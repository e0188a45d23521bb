#pragma once
// The bytes of a version 1.0 .npy header written by hand, as numpy writes it (the dict padded with spaces to a
// multiple of 64 bytes, ending in a newline): test files made without the library's own writer.
#include <cstddef>
#include <string>

namespace seqtopo::test_support {

inline std::string npy_v1_header(const std::string& descr, std::size_t rows, std::size_t cols) {
  std::string header = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': (" + std::to_string(rows) + ", " +
                       std::to_string(cols) + "), }";
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::string bytes = "\x93NUMPY\x01";
  bytes += '\0';
  bytes += static_cast<char>(header.size());
  bytes += '\0';
  return bytes + header;
}

}  // namespace seqtopo::test_support
