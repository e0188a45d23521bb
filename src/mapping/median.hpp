#pragma once
// The median of a sample (0 when empty), for the mapping module's estimates.
#include <algorithm>
#include <cstddef>
#include <vector>

namespace seqtopo::mapping::detail {

// Computed in double whatever the element type (a float sample gives the same median as its copy in double).
template <typename T>
double median(std::vector<T> v) {
  if (v.empty()) return 0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2 == 1) return static_cast<double>(*mid);
  const double upper = static_cast<double>(*mid);
  return 0.5 * (upper + static_cast<double>(*std::max_element(v.begin(), mid)));
}

}  // namespace seqtopo::mapping::detail
