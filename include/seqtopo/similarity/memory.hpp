#pragma once
// Memory estimates for the similarity matrix, so that a request that cannot fit is refused before the
// allocation instead of dying half-way.
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
// Memory this process may still use [bytes]: the smallest of MemAvailable (/proc/meminfo), the cgroup limit minus
// current use, and the environment variable SEQTOPO_MEMORY_LIMIT (bytes, or with a K, M or G suffix; a bad value
// throws InputError naming it); nullopt when none can be read.
std::optional<std::size_t> available_memory_bytes();
// The memory a run may plan for, independent of what other processes use at the moment (so that a choice made
// from it, such as the map's engine, is the same on every run on this machine): the smallest of MemTotal, the
// cgroup limit and SEQTOPO_MEMORY_LIMIT; nullopt when none can be read.
std::optional<std::size_t> memory_budget_bytes();
// "12.4 MiB", "3.1 GiB".
std::string format_bytes(std::size_t bytes);
// Throws MemoryError ("<what> needs X, only Y available") when `bytes` exceeds `available` (or the
// product overflowed, signalled by bytes == SIZE_MAX).
void check_fits(std::size_t bytes, std::optional<std::size_t> available, const std::string& what);

}  // namespace seqtopo::similarity
