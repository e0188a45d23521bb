#pragma once
// For readers that take a path: the fuzz input as a file in memory (a memfd), reachable as /proc/self/fd/N.
// One file per process, rewritten for every input, so a run touches no disk.
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace seqtopo::fuzz {

inline std::filesystem::path input_file(const std::uint8_t* data, std::size_t size) {
  static const int fd = [] {
    const int f = memfd_create("seqtopo-fuzz", 0);
    if (f < 0) std::abort();
    return f;
  }();
  if (ftruncate(fd, 0) != 0) std::abort();
  for (std::size_t done = 0; done < size;) {
    const ssize_t n = pwrite(fd, data + done, size - done, static_cast<off_t>(done));
    if (n <= 0) std::abort();
    done += static_cast<std::size_t>(n);
  }
  return "/proc/self/fd/" + std::to_string(fd);
}

}  // namespace seqtopo::fuzz
