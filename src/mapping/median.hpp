#pragma once
// The median of a sample (0 when empty), for the mapping module's estimates.
#include <algorithm>
#include <cstddef>
#include <vector>

namespace seqtopo::mapping::detail {

inline double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2 == 1) return *mid;
  const double upper = *mid;
  return 0.5 * (upper + *std::max_element(v.begin(), mid));
}

}  // namespace seqtopo::mapping::detail
