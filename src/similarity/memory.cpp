#include "seqtopo/similarity/memory.hpp"

#include <cstdio>
#include <limits>

namespace seqtopo::similarity {

std::size_t matrix_bytes(std::size_t rows, std::size_t cols) {
  constexpr std::size_t max = std::numeric_limits<std::size_t>::max();
  if (rows != 0 && cols > max / rows) return max;
  const std::size_t cells = rows * cols;
  return cells > max / sizeof(float) ? max : cells * sizeof(float);
}

std::string format_bytes(std::size_t bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  double value = static_cast<double>(bytes);
  int unit = 0;
  while (value >= 1024.0 && unit < 6) {
    value /= 1024.0;
    ++unit;
  }
  char text[32];
  std::snprintf(text, sizeof text, unit == 0 ? "%.0f %s" : "%.1f %s", value, units[unit]);
  return text;
}

void check_fits(std::size_t bytes, std::optional<std::size_t> available, const std::string& what) {
  if (bytes == std::numeric_limits<std::size_t>::max()) {
    throw MemoryError(what + " is too large to be addressed");
  }
  if (available && bytes > *available) {
    throw MemoryError(what + " needs " + format_bytes(bytes) + ", only " + format_bytes(*available) +
                      " of memory available");
  }
}

}  // namespace seqtopo::similarity
