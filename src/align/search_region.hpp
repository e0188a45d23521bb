#pragma once
// Which cells a pass searches, shared by every engine so that they search exactly the same ones.
#include <cstddef>
#include <utility>

#include "seqtopo/align/local_alignment.hpp"

namespace seqtopo::align::detail {

// Pass columns [lo, hi] (1-based, inclusive; lo > hi: none) that pass row i (1-based) may use, for a
// pass over n columns. A self alignment keeps one triangle, original pairs (r, c) with r - c >= min_separation.
inline std::pair<std::size_t, std::size_t> search_region(const AlignConfig& config, std::size_t n, std::size_t i) {
  if (!config.self) return {1, n};
  const std::size_t sep = config.min_separation;
  const std::size_t r = i - 1;  // row index in A
  if (config.direction == Direction::forward) {
    // original pair (r, c) with r - c >= sep  <=>  c <= r - sep
    if (r < sep) return {1, 0};
    return {1, r - sep + 1};
  }
  // reverse: pass column t (0-based) is original c = n-1-t; r - c >= sep  <=>  t >= n-1-r+sep
  const std::size_t t_lo = n - 1 - r + sep;
  if (t_lo >= n) return {1, 0};
  return {t_lo + 1, n};
}

}  // namespace seqtopo::align::detail
