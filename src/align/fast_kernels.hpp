#pragma once
// Row kernels of the fast engine (one per instruction set) and what they share. Private to src/align.
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "seqtopo/align/fast_alignment.hpp"

namespace seqtopo::align::detail {

// Every row buffer (H values and scores) is indexed by pass column j = 0 .. n and padded with
// kRowPadding readable elements after n, so a kernel may read a whole vector past the last column.
inline constexpr std::size_t kRowPadding = 32;
// A forbidden pair (already used by an alignment): no diagonal step may enter it. Adding this to any
// cell value <= 32767 gives a negative number, so the step never wins and is never tight.
inline constexpr std::int16_t kForbidden = -32768;
inline constexpr int kMaxStep = 32767;

// One row of H(i, j) = min(cap, max(0, H(i-1, j-1) + S(i, j), H(i-1, j) - gap_a, H(i, j-1) - gap_b))
// over columns [lo, hi] (1-based, lo <= hi), with H(i, lo - 1) = left, in saturating int16 arithmetic.
// prev and cur are H rows, score[j] = S(i, j). Reads prev[lo - 1 .. hi] and score[lo .. hi] only and
// writes cur[lo .. hi] only (column strips of one row may run on different threads). Returns the
// maximum of cur[lo .. hi] (0 if none is positive). With column_max set, also column_max[j] =
// max(column_max[j], cur[j]) for j in [lo, hi] (the fill's maxima of a band of rows, while cur is in a register).
struct RowJob {
  const std::int16_t* prev;
  std::int16_t* cur;
  const std::int16_t* score;
  std::size_t lo, hi;
  std::int16_t gap_a, gap_b, cap;
  std::int16_t left = 0;
  std::int16_t* column_max = nullptr;
};
using RowKernel = std::int16_t (*)(const RowJob&);

// out[k] = quantize(in[k] * scale) for k < count (the rule of fast_alignment.hpp).
using Quantizer = void (*)(const float* in, std::size_t count, float scale, std::int16_t* out);

std::int16_t row_scalar(const RowJob& job);
std::int16_t row_sse41(const RowJob& job);
std::int16_t row_avx2(const RowJob& job);
void quantize_scalar(const float* in, std::size_t count, float scale, std::int16_t* out);
void quantize_sse41(const float* in, std::size_t count, float scale, std::int16_t* out);
void quantize_avx2(const float* in, std::size_t count, float scale, std::int16_t* out);

// The one scalar definition of quantization; the vector quantizers compute exactly this.
std::int16_t quantize_one(float value, float scale);

// Saturating int16 arithmetic on ints.
inline int saturate(int v) { return v > kMaxStep ? kMaxStep : (v < -32768 ? -32768 : v); }

// Per-lane gap multiples: steps[k] = saturate((k + 1) * gap) for k < lanes.
inline void gap_multiples(int gap, int lanes, std::int16_t* steps) {
  for (int k = 0; k < lanes; ++k) steps[k] = static_cast<std::int16_t>(saturate(std::min(gap, kMaxStep) * (k + 1)));
}

}  // namespace seqtopo::align::detail
