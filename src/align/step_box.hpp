#pragma once
// The rectangle of one alignment, from its start to its end, with the tight steps into every cell an
// optimal path can use, and the path through it by recursive bisection. Shared by the scalar engine
// (smith_waterman.cpp) and the fast engine (fast_alignment.cpp): both fill the step bits from their own
// tables, then take the same path, so their alignments agree pair for pair.
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"

namespace seqtopo::align::detail {

using BoxCell = std::pair<std::size_t, std::size_t>;  // (row, column) relative to the start

// Step bits: 1 diagonal step into the cell, 2 step down into it, 4 step right into it.
struct StepBox {
  std::size_t r0 = 0, c0 = 0;  // the start (the zero cell before the first pair), pass coordinates
  std::vector<std::size_t> lo, hi, offset;
  std::vector<std::uint8_t> steps, fwd, bwd;  // fwd, bwd: scratch flags of the bisection

  // Row 0 holds the start alone; row r >= 1 the pass columns spans[rows - 1 - r] (first, last) that reach
  // the end, clipped to the right of the start. Step bits start at 0.
  void layout(BoxCell start, const std::vector<std::pair<std::size_t, std::size_t>>& spans, std::size_t rows);

  bool inside(std::size_t r, std::size_t c) const { return c >= lo[r] && c <= hi[r]; }
  std::size_t index(std::size_t r, std::size_t c) const { return offset[r] + (c - lo[r]); }
  std::uint8_t at(std::size_t r, std::size_t c) const { return inside(r, c) ? steps[index(r, c)] : 0; }
  bool diag(std::size_t r, std::size_t c) const { return (at(r, c) & 1U) != 0; }
  bool down(std::size_t r, std::size_t c) const { return (at(r, c) & 2U) != 0; }
  bool right(std::size_t r, std::size_t c) const { return (at(r, c) & 4U) != 0; }
  bool f(std::size_t r, std::size_t c) const { return inside(r, c) && fwd[index(r, c)] != 0; }
  bool b(std::size_t r, std::size_t c) const { return inside(r, c) && bwd[index(r, c)] != 0; }
};

// The path between two cells p and q of an optimal alignment (box coordinates), by recursive bisection
// (Myers-Miller, as in SIM): the path crosses the middle row at the leftmost possible column, unless it
// can cross further right at a cell it enters by a diagonal or rightward step only and leaves downwards,
// in which case at the rightmost such cell. A single row takes no pair if a gap-only route is optimal,
// else its leftmost possible pair. Appends the pairs (box cells of the diagonal steps) in order.
void bisect(StepBox& box, BoxCell p, BoxCell q, std::vector<std::pair<std::size_t, std::size_t>>& pairs);

// The alignment from the start of `box` to `end` (pass coordinates): its pairs in original indices (the
// reverse pass reads column j of B as n - j) and its ranges. Throws std::logic_error if it has no pair.
LocalAlignment alignment_through(StepBox& box, BoxCell end, Direction direction, std::size_t n, Score score);

}  // namespace seqtopo::align::detail
