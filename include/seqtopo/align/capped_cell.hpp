#pragma once
// The one cell of the capped Smith-Waterman recurrence (smith_waterman.hpp, the mapping paper's cap):
//   H(i, j) = min(cap, max(0, H(i-1, j-1) + S(i-1, j-1), H(i-1, j) - gap_a, H(i, j-1) - gap_b))
// in one evaluation order, so that every engine that evaluates it in float (the exact engine, locally optimal
// alignments, the sparse components, the online mapper and localizer) gets the same bits from the same inputs.
// The vectorized engine (fast_alignment.hpp) evaluates the same recurrence on quantized integers.
#include <algorithm>
#include <optional>

namespace seqtopo::align {

// The capped score (the cap unset: none).
inline float capped(float v, const std::optional<float>& cap) { return cap ? std::min(v, *cap) : v; }

// A cell from its diagonal step's value (H(i-1, j-1) + S, or 0 where the diagonal step is forbidden), its upper
// and left neighbours; neighbours outside the table are 0.
inline float capped_cell(float diagonal_step, float up, float left, float gap_a, float gap_b,
                         const std::optional<float>& cap) {
  float v = std::max(0.0F, diagonal_step);
  v = std::max(v, up - gap_a);
  v = std::max(v, left - gap_b);
  return capped(v, cap);
}

}  // namespace seqtopo::align
