#pragma once
// Memory estimates for the similarity matrix, so that a request that cannot fit is refused before the
// allocation instead of dying half-way. How much memory there is is the caller's to say (a byte budget): the job
// layer reads the machine (pipeline/machine_memory.hpp).
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>

namespace seqtopo::similarity {

class MemoryError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Bytes of an N x M float matrix (the distance matrix is turned into the similarity matrix in place).
std::size_t matrix_bytes(std::size_t rows, std::size_t cols);
// "12.4 MiB", "3.1 GiB".
std::string format_bytes(std::size_t bytes);
// Throws MemoryError ("<what> needs X, only Y available") when `bytes` exceeds `available` (or the
// product overflowed, signalled by bytes == SIZE_MAX).
void check_fits(std::size_t bytes, std::optional<std::size_t> available, const std::string& what);

}  // namespace seqtopo::similarity
