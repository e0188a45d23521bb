// SSE4.1 and AVX2 row kernels, compiled for their instruction set through function attributes (no
// per-file flags) and chosen at run time.
//
// A row is computed in two steps: T(j) = min(cap, max(0, diagonal, down)) needs only the row above;
// then H(j) = max over k <= j of T(k) - (j - k) * gap_b is a running maximum with linear decay, done
// inside a vector by log2(lanes) shift-and-max steps and across vectors by one scalar carry.
// Most vectors need no gap step inside them (one shift and compare tell), so the scan is skipped there.
// Saturation only ever clips values far below 0, which the max with T >= 0 discards, so the result
// equals the scalar kernel's.
#include "fast_kernels.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>

#include <algorithm>

namespace seqtopo::align::detail {
namespace {

#define SEQTOPO_SSE41 [[gnu::target("sse4.1"), gnu::always_inline]] inline
#define SEQTOPO_AVX2 [[gnu::target("avx2"), gnu::always_inline]] inline

SEQTOPO_SSE41 int hmax_sse41(__m128i v) {
  // values are >= 0: the maximum is 32767 minus the unsigned minimum of 32767 - v
  const __m128i flipped = _mm_sub_epi16(_mm_set1_epi16(32767), v);
  return 32767 - _mm_extract_epi16(_mm_minpos_epu16(flipped), 0);
}

SEQTOPO_AVX2 __m256i shift_lanes_avx2_1(__m256i x) {
  return _mm256_alignr_epi8(x, _mm256_permute2x128_si256(x, x, 0x08), 14);
}
SEQTOPO_AVX2 __m256i shift_lanes_avx2_2(__m256i x) {
  return _mm256_alignr_epi8(x, _mm256_permute2x128_si256(x, x, 0x08), 12);
}
SEQTOPO_AVX2 __m256i shift_lanes_avx2_4(__m256i x) {
  return _mm256_alignr_epi8(x, _mm256_permute2x128_si256(x, x, 0x08), 8);
}
SEQTOPO_AVX2 __m256i shift_lanes_avx2_8(__m256i x) { return _mm256_permute2x128_si256(x, x, 0x08); }

#undef SEQTOPO_SSE41
#undef SEQTOPO_AVX2

}  // namespace

[[gnu::target("sse4.1")]] std::int16_t row_sse41(const RowJob& job) {
  constexpr std::size_t kLanes = 8;
  alignas(16) std::int16_t steps[kLanes];
  gap_multiples(job.gap_b, kLanes, steps);
  const __m128i gap_a = _mm_set1_epi16(job.gap_a), cap = _mm_set1_epi16(job.cap), zero = _mm_setzero_si128();
  const __m128i g1 = _mm_set1_epi16(steps[0]), g2 = _mm_set1_epi16(steps[1]), g4 = _mm_set1_epi16(steps[3]);
  const __m128i carry_steps = _mm_load_si128(reinterpret_cast<const __m128i*>(steps));
  const __m128i lane = _mm_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7);
  const int g8 = steps[7];
  __m128i best = zero;
  int carry = job.left;  // H(i, j - 1)
  alignas(32) std::int16_t tail_prev[kLanes + 1], tail_score[kLanes], tail_out[kLanes];
  // locals: a vector store may alias anything, so fields of job would be reloaded every iteration
  const std::size_t lo = job.lo, hi = job.hi;
  const std::int16_t* const prev = job.prev;
  const std::int16_t* const score = job.score;
  std::int16_t* const cur = job.cur;
  for (std::size_t j = lo; j <= hi; j += kLanes) {
    const std::int16_t* up = prev + j - 1;
    const std::int16_t* sc = score + j;
    const bool tail = j + kLanes - 1 > hi;
    if (tail) {  // the last, partial vector goes through local copies: nothing past hi is read or written
      const std::size_t count = hi - j + 1;
      std::fill(tail_prev, tail_prev + kLanes + 1, std::int16_t{0});
      std::fill(tail_score, tail_score + kLanes, std::int16_t{0});
      std::copy(up, up + count + 1, tail_prev);
      std::copy(sc, sc + count, tail_score);
      up = tail_prev;
      sc = tail_score;
    }
    const __m128i d = _mm_loadu_si128(reinterpret_cast<const __m128i*>(up));
    const __m128i u = _mm_loadu_si128(reinterpret_cast<const __m128i*>(up + 1));
    const __m128i s = _mm_loadu_si128(reinterpret_cast<const __m128i*>(sc));
    __m128i x = _mm_max_epi16(_mm_max_epi16(_mm_adds_epi16(d, s), _mm_subs_epi16(u, gap_a)), zero);
    x = _mm_min_epi16(x, cap);
    const __m128i step = _mm_subs_epi16(_mm_slli_si128(x, 2), g1);
    const __m128i better = _mm_cmpgt_epi16(step, x);
    if (!_mm_testz_si128(better, better)) {  // some gap step inside the vector helps: finish the scan
      x = _mm_max_epi16(x, step);
      x = _mm_max_epi16(x, _mm_subs_epi16(_mm_slli_si128(x, 4), g2));
      x = _mm_max_epi16(x, _mm_subs_epi16(_mm_slli_si128(x, 8), g4));
    }
    const int last = static_cast<std::int16_t>(_mm_extract_epi16(x, 7));
    x = _mm_max_epi16(x, _mm_subs_epi16(_mm_set1_epi16(static_cast<std::int16_t>(carry)), carry_steps));
    if (tail) {
      const std::size_t count = hi - j + 1;
      x = _mm_and_si128(x, _mm_cmpgt_epi16(_mm_set1_epi16(static_cast<std::int16_t>(count)), lane));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(tail_out), x);
      std::copy(tail_out, tail_out + count, cur + j);
    } else {
      _mm_storeu_si128(reinterpret_cast<__m128i*>(cur + j), x);
    }
    best = _mm_max_epi16(best, x);
    carry = std::max(last, saturate(carry - g8));
  }
  return static_cast<std::int16_t>(hmax_sse41(best));
}

[[gnu::target("avx2")]] std::int16_t row_avx2(const RowJob& job) {
  constexpr std::size_t kLanes = 16;
  alignas(32) std::int16_t steps[kLanes];
  gap_multiples(job.gap_b, kLanes, steps);
  const __m256i gap_a = _mm256_set1_epi16(job.gap_a), cap = _mm256_set1_epi16(job.cap), zero = _mm256_setzero_si256();
  const __m256i g1 = _mm256_set1_epi16(steps[0]), g2 = _mm256_set1_epi16(steps[1]);
  const __m256i g4 = _mm256_set1_epi16(steps[3]), g8 = _mm256_set1_epi16(steps[7]);
  const __m256i carry_steps = _mm256_load_si256(reinterpret_cast<const __m256i*>(steps));
  const __m256i lane = _mm256_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const int g16 = steps[15];
  __m256i best = zero;
  int carry = job.left;  // H(i, j - 1)
  alignas(32) std::int16_t tail_prev[kLanes + 1], tail_score[kLanes], tail_out[kLanes];
  // locals: a vector store may alias anything, so fields of job would be reloaded every iteration
  const std::size_t lo = job.lo, hi = job.hi;
  const std::int16_t* const prev = job.prev;
  const std::int16_t* const score = job.score;
  std::int16_t* const cur = job.cur;
  for (std::size_t j = lo; j <= hi; j += kLanes) {
    const std::int16_t* up = prev + j - 1;
    const std::int16_t* sc = score + j;
    const bool tail = j + kLanes - 1 > hi;
    if (tail) {  // the last, partial vector goes through local copies: nothing past hi is read or written
      const std::size_t count = hi - j + 1;
      std::fill(tail_prev, tail_prev + kLanes + 1, std::int16_t{0});
      std::fill(tail_score, tail_score + kLanes, std::int16_t{0});
      std::copy(up, up + count + 1, tail_prev);
      std::copy(sc, sc + count, tail_score);
      up = tail_prev;
      sc = tail_score;
    }
    const __m256i d = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(up));
    const __m256i u = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(up + 1));
    const __m256i s = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(sc));
    __m256i x = _mm256_max_epi16(_mm256_max_epi16(_mm256_adds_epi16(d, s), _mm256_subs_epi16(u, gap_a)), zero);
    x = _mm256_min_epi16(x, cap);
    const __m256i step = _mm256_subs_epi16(shift_lanes_avx2_1(x), g1);
    const __m256i better = _mm256_cmpgt_epi16(step, x);
    if (!_mm256_testz_si256(better, better)) {  // some gap step inside the vector helps: finish the scan
      x = _mm256_max_epi16(x, step);
      x = _mm256_max_epi16(x, _mm256_subs_epi16(shift_lanes_avx2_2(x), g2));
      x = _mm256_max_epi16(x, _mm256_subs_epi16(shift_lanes_avx2_4(x), g4));
      x = _mm256_max_epi16(x, _mm256_subs_epi16(shift_lanes_avx2_8(x), g8));
    }
    const int last = static_cast<std::int16_t>(_mm256_extract_epi16(x, 15));
    x = _mm256_max_epi16(x, _mm256_subs_epi16(_mm256_set1_epi16(static_cast<std::int16_t>(carry)), carry_steps));
    if (tail) {
      const std::size_t count = hi - j + 1;
      x = _mm256_and_si256(x, _mm256_cmpgt_epi16(_mm256_set1_epi16(static_cast<std::int16_t>(count)), lane));
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(tail_out), x);
      std::copy(tail_out, tail_out + count, cur + j);
    } else {
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(cur + j), x);
    }
    best = _mm256_max_epi16(best, x);
    carry = std::max(last, saturate(carry - g16));
  }
  const __m128i half = _mm_max_epi16(_mm256_castsi256_si128(best), _mm256_extracti128_si256(best, 1));
  const __m128i flipped = _mm_sub_epi16(_mm_set1_epi16(32767), half);
  return static_cast<std::int16_t>(32767 - _mm_extract_epi16(_mm_minpos_epu16(flipped), 0));
}

// Same order of operations as quantize_one: max with -32767 first (its NaN rule), min, round to
// nearest even, convert (exact), pack.
[[gnu::target("sse4.1")]] void quantize_sse41(const float* in, std::size_t count, float scale, std::int16_t* out) {
  const __m128 s = _mm_set1_ps(scale), lo = _mm_set1_ps(-32767.0F), hi = _mm_set1_ps(32767.0F);
  std::size_t k = 0;
  for (; k + 8 <= count; k += 8) {
    __m128 a = _mm_mul_ps(_mm_loadu_ps(in + k), s), b = _mm_mul_ps(_mm_loadu_ps(in + k + 4), s);
    a = _mm_min_ps(_mm_max_ps(a, lo), hi);
    b = _mm_min_ps(_mm_max_ps(b, lo), hi);
    a = _mm_round_ps(a, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
    b = _mm_round_ps(b, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + k), _mm_packs_epi32(_mm_cvtps_epi32(a), _mm_cvtps_epi32(b)));
  }
  for (; k < count; ++k) out[k] = quantize_one(in[k], scale);
}

[[gnu::target("avx2")]] void quantize_avx2(const float* in, std::size_t count, float scale, std::int16_t* out) {
  const __m256 s = _mm256_set1_ps(scale), lo = _mm256_set1_ps(-32767.0F), hi = _mm256_set1_ps(32767.0F);
  std::size_t k = 0;
  for (; k + 8 <= count; k += 8) {
    __m256 a = _mm256_mul_ps(_mm256_loadu_ps(in + k), s);
    a = _mm256_min_ps(_mm256_max_ps(a, lo), hi);
    a = _mm256_round_ps(a, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
    const __m256i w = _mm256_cvtps_epi32(a);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + k),
                     _mm_packs_epi32(_mm256_castsi256_si128(w), _mm256_extracti128_si256(w, 1)));
  }
  for (; k < count; ++k) out[k] = quantize_one(in[k], scale);
}

}  // namespace seqtopo::align::detail

#else
// Other CPUs: best_isa() reports scalar; these exist only so the dispatch table links.
namespace seqtopo::align::detail {
std::int16_t row_sse41(const RowJob& job) { return row_scalar(job); }
std::int16_t row_avx2(const RowJob& job) { return row_scalar(job); }
void quantize_sse41(const float* in, std::size_t count, float scale, std::int16_t* out) { quantize_scalar(in, count, scale, out); }
void quantize_avx2(const float* in, std::size_t count, float scale, std::int16_t* out) { quantize_scalar(in, count, scale, out); }
}  // namespace seqtopo::align::detail
#endif
