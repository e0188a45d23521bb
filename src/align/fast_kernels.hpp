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

// The fill's kernels: whole rows of a column strip in a striped layout (Farrar 2007) built on the tiles.
// A strip of columns lo .. lo + width - 1 (lo - 1 a multiple of the block width) is cut into blocks of
// kTileSide x lanes columns; lane l of a block is one tile's columns and vector s of the block holds
// column s of each of its tiles, so column rel = j - lo sits at striped_index(rel, lanes). A row is one
// pass over each block's vectors (the diagonal and upward steps, and the gap_b step from vector s - 1
// to s inside each tile), then the lazy-F loop carries the gap_b step from each tile's last column into
// the next tile's first until no lane improves.
inline constexpr std::size_t kTileSide = 32;
inline std::size_t striped_index(std::size_t rel, std::size_t lanes) {
  const std::size_t block = kTileSide * lanes, in = rel % block;
  return rel - in + (in % kTileSide) * lanes + in / kTileSide;
}

// One row i of a strip, rows in the striped layout (elements int16 or int8, as the kernel's name says).
// Columns outside [rlo, rhi) (relative to the strip, rlo < rhi <= width) are outside the searched
// region: H = 0 there, whatever their scores; blocks with no searched column are not touched (they are
// all 0 in both rows: a pass's region only grows from row to row). Reads prev and score and writes cur
// over the touched blocks. tile_max[t] = max(tile_max[t], H(i, column of tile t)) for the tiles of the
// touched blocks (natural order, int16); columns, if set, gets H(i, lo - 1 + 32 (q + 1)) for every tile q
// of a touched block that is whole (lo - 1 + 32 (q + 1) <= lo - 1 + width). Returns the row's maximum.
// Scores past the strip's end (padding up to the whole block) must be <= 0.
//
// int16 rows hold H. int8 rows hold H - 128 (so 0 is -128, which is where a row starts), for H in
// [0, 255]: signed saturation at -128 is exactly the floor at H = 0. They are exact for scores in
// [-128, 127] (scores are saturated to int8) and gaps <= kInt8Gap, if the cap is below kInt8Limit;
// otherwise, with the cap clipped to 255, whenever the row's maximum (the result), left and diag_left
// are below kInt8Limit. The fill redoes a row that is not in int16, and goes on in int16, keeping
// nothing such a row wrote: its cells are lower bounds of the true ones (saturation clips from above
// only), but the fill does not rely on that and puts the band's tile maxima back as they were.
struct CarryHint;
struct StripedJob {
  const void* prev;
  void* cur;
  const void* score;
  std::size_t width;             // columns of the strip
  std::size_t rlo, rhi;          // searched columns of the row, relative to the strip
  std::int16_t left, diag_left;  // H(i, lo - 1), H(i - 1, lo - 1)
  std::int16_t gap_a, gap_b, cap;
  std::int16_t* tile_max;
  std::int16_t* columns = nullptr;
  struct CarryHint* carry = nullptr;  // kept from row to row by the caller (speed only; 8 steps if not set)
  // int16 kernels: score holds int8 scores in the int8 striped layout of the same strip (twice the lanes
  // per block), widened as they are loaded: a profile of scores that fit int8 needs no int16 copy.
  bool score8 = false;
};

// How many vectors of a block the kernel's lazy-F pass writes without testing whether they improve:
// doubled when more than a quarter of the blocks needed more, halved when fewer than 1 in 32 did
// (counted over at least 256 blocks, between 2 and 16 steps). Only the speed depends on it.
struct CarryHint {
  std::size_t steps = 8, blocks = 0, further = 0;
};
using StripedKernel = std::int16_t (*)(const StripedJob&);
inline constexpr int kInt8Limit = 255;   // an int8 row whose maximum reaches this may have saturated
inline constexpr int kInt8Gap = 127;     // the largest gap an int8 row takes
inline constexpr int kInt8Offset = 128;  // int8 rows hold H - 128

// One whole block of scores from natural order into the striped layout: out[s * lanes + l] = in[32 l + s]
// (saturated to int8 by the int8 ones). lanes: 8 / 16 (sse4.1 int16 / int8), 16 / 32 (avx2).
using BlockStriper16 = void (*)(const std::int16_t* in, std::int16_t* out);
using BlockStriper8 = void (*)(const std::int16_t* in, std::int8_t* out);
void stripe16_sse41(const std::int16_t* in, std::int16_t* out);
void stripe8_sse41(const std::int16_t* in, std::int8_t* out);
void stripe16_avx2(const std::int16_t* in, std::int16_t* out);
void stripe8_avx2(const std::int16_t* in, std::int8_t* out);
// The inverse, as H: out[32 l + s] = H of in[s * lanes + l] (int8 rows hold H - 128).
using BlockDestriper16 = void (*)(const std::int16_t* in, std::int16_t* out);
using BlockDestriper8 = void (*)(const std::int8_t* in, std::int16_t* out);
void destripe16_sse41(const std::int16_t* in, std::int16_t* out);
void destripe8_sse41(const std::int8_t* in, std::int16_t* out);
void destripe16_avx2(const std::int16_t* in, std::int16_t* out);
void destripe8_avx2(const std::int8_t* in, std::int16_t* out);

std::int16_t striped16_sse41(const StripedJob& job);
std::int16_t striped16_avx2(const StripedJob& job);
std::int16_t striped8_sse41(const StripedJob& job);
std::int16_t striped8_avx2(const StripedJob& job);

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
