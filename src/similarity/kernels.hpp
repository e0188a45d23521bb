#pragma once
// The inner loops shared by the pairwise functions and the matrix.
//
// Dense vectors: every sum runs over eight lanes (element k goes to lane k % 8, lanes combined as
// ((0 + 1) + (2 + 3)) + ((4 + 5) + (6 + 7))), terms in float, sums in double. Sparse histograms: see
// sparse_sums below. Either way the order of every sum is fixed by the code, not by the compiler or the
// thread, so every result is reproducible, and the eight independent lanes fill one AVX2 register.
#include <cstddef>
#include <cstdint>

namespace seqtopo::similarity::detail {

double lane_sum_squares(const float* values, std::size_t n);

// Sparse histograms are compared eight rows at a time: the stored bins of rows r = 0..7 are scattered into
// `a8` (a8[bin * 8 + r], zero elsewhere), and one pass over the stored bins of histogram B gives the eight
// sums at once with plain 8-wide vector arithmetic (one 32-byte load per bin of B, no gather). Each row's
// sum runs over B's bins in order, in float over blocks of 64 bins, the block sums added in double; a row's
// result therefore does not depend on which rows share its pass, and the pairwise functions (row 0 alone)
// give exactly the matrix's value.
constexpr std::size_t kRows = 8;
enum class SparseSum { chi2, l1, dot };
//   chi2: sum_k ((x - y)^2 / (x + y) - x)   the distance is sum(A) + this: bins of A that B does not store
//   l1:   sum_k (|x - y| - x)               contribute their term x, so only B's bins are visited
//   dot:  sum_k x * y
// with x = a8[bins[k] * 8 + r], y = values[k] (> 0, so x + y > 0).
void sparse_sums(SparseSum kind, const float* a8, const std::uint32_t* bins, const float* values, std::size_t n,
                 double (&out)[kRows]);
// sum(A) and |A|^2 in the same order and precision as sparse_sums, so that identical histograms give exactly
// 0 (every chi2 / l1 term is then exactly -x, every dot term x * x).
double sparse_sum(const float* values, std::size_t n);
double sparse_sum_squares(const float* values, std::size_t n);

double dense_chi2(const float* a, const float* b, std::size_t n);  // 0/0 terms skipped (paper eq. 1)

// Dense vectors on a grid of 2^-shift (every value q * 2^-shift with an integer |q| <= 127, as the patch
// thumbnails are) are stored as q + 128 in one byte each, and their L1 distance is the integer sum of |q_a -
// q_b| (psadbw: 32 bytes an instruction), times 2^-shift. That is exactly dense_l1 of the float values: each
// |x - y| and every partial sum of dense_l1 is then a multiple of 2^-shift below 2^53 of them, so exact.
bool on_byte_grid(const float* values, std::size_t n, int shift);
void to_bytes(const float* values, std::size_t n, int shift, std::uint8_t* out);
// out[c] = sum_k |a[k] - b[c][k]| for the four vectors b[0..3] (one pass over a).
void byte_l1_4(const std::uint8_t* a, const std::uint8_t* const (&b)[4], std::size_t n, std::uint64_t (&out)[4]);
std::uint64_t byte_l1(const std::uint8_t* a, const std::uint8_t* b, std::size_t n);
double dense_l1(const float* a, const float* b, std::size_t n);
double dense_dot(const float* a, const float* b, std::size_t n);

// 1 - dot / sqrt(|a|^2 |b|^2), clamped to [0, 2]: sqrt(x * x) == x exactly, so identical vectors give
// exactly 0. Zero vectors: 0 against each other, 1 against anything else.
double cosine_from_dot(double dot, double norm2_a, double norm2_b);

}  // namespace seqtopo::similarity::detail
