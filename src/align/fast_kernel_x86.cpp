// SSE4.1 and AVX2 row kernels, compiled for their instruction set through function attributes (no
// per-file flags) and chosen at run time. One body (SEQTOPO_ROW_KERNEL) serves both widths: GCC will
// not inline target-specific intrinsics into a template without that target, so the body is a macro
// over a per-width traits struct whose members carry the target.
//
// A row is computed in two steps: T(j) = min(cap, max(0, diagonal, down)) needs only the row above;
// then H(j) = max over k <= j of T(k) - (j - k) * gap_b is a running maximum with linear decay, done
// inside a vector by shift-and-max steps (within 128-bit halves, then one step across them) and across
// vectors by a carry H(i, j - 1) kept in every lane. The scan is done for every vector, without a test:
// a data-dependent branch there is mispredicted often enough to cost more than the scan, and without it
// the only serial dependency between vectors is the carry's subtract and max, so consecutive vectors
// overlap. The carry stays in a vector: moving it through a general register costs more shuffles.
// Saturation only ever clips values far below 0, which the max with T >= 0 discards, so the result
// equals the scalar kernel's.
#include "fast_kernels.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>

#include <algorithm>

namespace seqtopo::align::detail {
namespace {

#define SEQTOPO_SSE41 [[gnu::target("sse4.1"), gnu::always_inline]] static inline
#define SEQTOPO_AVX2 [[gnu::target("avx2"), gnu::always_inline]] static inline

struct Sse41 {
  using V = __m128i;
  static constexpr std::size_t kLanes = 8;
  SEQTOPO_SSE41 V load(const std::int16_t* p) { return _mm_loadu_si128(reinterpret_cast<const V*>(p)); }
  SEQTOPO_SSE41 void store(std::int16_t* p, V v) { _mm_storeu_si128(reinterpret_cast<V*>(p), v); }
  SEQTOPO_SSE41 V set1(int v) { return _mm_set1_epi16(static_cast<std::int16_t>(v)); }
  SEQTOPO_SSE41 V zero() { return _mm_setzero_si128(); }
  SEQTOPO_SSE41 V adds(V a, V b) { return _mm_adds_epi16(a, b); }
  SEQTOPO_SSE41 V subs(V a, V b) { return _mm_subs_epi16(a, b); }
  SEQTOPO_SSE41 V max(V a, V b) { return _mm_max_epi16(a, b); }
  SEQTOPO_SSE41 V min(V a, V b) { return _mm_min_epi16(a, b); }
  // steps[k] = (k + 1) * gap for k < lanes (saturated): the scan's decay
  SEQTOPO_SSE41 V scan(V x, const std::int16_t* steps) {
    x = _mm_max_epi16(x, _mm_subs_epi16(_mm_slli_si128(x, 2), _mm_set1_epi16(steps[0])));
    x = _mm_max_epi16(x, _mm_subs_epi16(_mm_slli_si128(x, 4), _mm_set1_epi16(steps[1])));
    return _mm_max_epi16(x, _mm_subs_epi16(_mm_slli_si128(x, 8), _mm_set1_epi16(steps[3])));
  }
  SEQTOPO_SSE41 V last(V x) { return _mm_shuffle_epi8(x, _mm_set1_epi16(0x0f0e)); }  // lane 7 everywhere
  SEQTOPO_SSE41 int hmax(V v) {  // values are >= 0: 32767 minus the unsigned minimum of 32767 - v
    return 32767 - _mm_extract_epi16(_mm_minpos_epu16(_mm_sub_epi16(_mm_set1_epi16(32767), v)), 0);
  }
};

struct Avx2 {
  using V = __m256i;
  static constexpr std::size_t kLanes = 16;
  SEQTOPO_AVX2 V load(const std::int16_t* p) { return _mm256_loadu_si256(reinterpret_cast<const V*>(p)); }
  SEQTOPO_AVX2 void store(std::int16_t* p, V v) { _mm256_storeu_si256(reinterpret_cast<V*>(p), v); }
  SEQTOPO_AVX2 V set1(int v) { return _mm256_set1_epi16(static_cast<std::int16_t>(v)); }
  SEQTOPO_AVX2 V zero() { return _mm256_setzero_si256(); }
  SEQTOPO_AVX2 V adds(V a, V b) { return _mm256_adds_epi16(a, b); }
  SEQTOPO_AVX2 V subs(V a, V b) { return _mm256_subs_epi16(a, b); }
  SEQTOPO_AVX2 V max(V a, V b) { return _mm256_max_epi16(a, b); }
  SEQTOPO_AVX2 V min(V a, V b) { return _mm256_min_epi16(a, b); }
  // Byte shifts stay inside each 128-bit half (one cheap shuffle each); then lane 7 of the low half,
  // decayed by 1..8 steps, reaches the high half. The low half of `from_low` is 0, below every x.
  SEQTOPO_AVX2 V scan(V x, const std::int16_t* steps) {
    x = _mm256_max_epi16(x, _mm256_subs_epi16(_mm256_slli_si256(x, 2), _mm256_set1_epi16(steps[0])));
    x = _mm256_max_epi16(x, _mm256_subs_epi16(_mm256_slli_si256(x, 4), _mm256_set1_epi16(steps[1])));
    x = _mm256_max_epi16(x, _mm256_subs_epi16(_mm256_slli_si256(x, 8), _mm256_set1_epi16(steps[3])));
    const V lane7 = _mm256_set1_epi16(0x0f0e);
    const V from_low = _mm256_shuffle_epi8(_mm256_permute2x128_si256(x, x, 0x08), lane7);
    const V half_steps = _mm256_broadcastsi128_si256(_mm_loadu_si128(reinterpret_cast<const __m128i*>(steps)));
    return _mm256_max_epi16(x, _mm256_subs_epi16(from_low, half_steps));
  }
  SEQTOPO_AVX2 V last(V x) {  // lane 15 everywhere
    return _mm256_shuffle_epi8(_mm256_permute2x128_si256(x, x, 0x11), _mm256_set1_epi16(0x0f0e));
  }
  SEQTOPO_AVX2 int hmax(V v) {
    const __m128i half = _mm_max_epi16(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
    return 32767 - _mm_extract_epi16(_mm_minpos_epu16(_mm_sub_epi16(_mm_set1_epi16(32767), half)), 0);
  }
};

#undef SEQTOPO_SSE41
#undef SEQTOPO_AVX2

}  // namespace

// One vector of H from the row above (up = prev + j - 1) and the scores (sc = score + j): defines x
// and advances carry.
#define SEQTOPO_ROW_VECTOR(W, up, sc)                                                                  \
  W::V x = W::max(W::max(W::adds(W::load(up), W::load(sc)), W::subs(W::load((up) + 1), gap_a)), zero); \
  x = W::scan(W::min(x, cap), steps);                                                                  \
  const W::V last = W::last(x);                                                                        \
  x = W::max(x, W::subs(carry, carry_steps));                                                          \
  carry = W::max(last, W::subs(carry, g_all));

// The body of row_sse41 / row_avx2 over traits W. The saturating subtractions from the carry never
// saturate: carry is in [0, 32767] and a gap step at most 32767.
#define SEQTOPO_ROW_KERNEL(W)                                                                         \
  constexpr std::size_t kLanes = W::kLanes;                                                           \
  alignas(32) std::int16_t steps[kLanes];                                                             \
  gap_multiples(job.gap_b, kLanes, steps);                                                            \
  const W::V gap_a = W::set1(job.gap_a), cap = W::set1(job.cap), zero = W::zero();                    \
  const W::V carry_steps = W::load(steps);                                                            \
  const W::V g_all = W::set1(steps[kLanes - 1]);                                                      \
  W::V best = zero;                                                                                   \
  W::V carry = W::set1(job.left); /* H(i, j - 1) in every lane */                                     \
  /* locals: a vector store may alias anything, so fields of job would be reloaded every iteration */ \
  const std::size_t lo = job.lo, hi = job.hi;                                                         \
  const std::int16_t* const prev = job.prev;                                                          \
  const std::int16_t* const score = job.score;                                                        \
  std::int16_t* const cur = job.cur;                                                                  \
  std::int16_t* const column_max = job.column_max;                                                    \
  std::size_t j = lo;                                                                                 \
  for (; j + kLanes - 1 <= hi; j += kLanes) {                                                         \
    SEQTOPO_ROW_VECTOR(W, prev + j - 1, score + j)                                                    \
    W::store(cur + j, x);                                                                             \
    best = W::max(best, x);                                                                           \
    if (column_max) W::store(column_max + j, W::max(W::load(column_max + j), x));                     \
  }                                                                                                   \
  if (j <= hi) { /* the last, partial vector goes through local copies: nothing past hi is touched */ \
    const std::size_t count = hi - j + 1;                                                             \
    alignas(32) std::int16_t tail_prev[kLanes + 1] = {}, tail_score[kLanes] = {}, tail_out[kLanes];   \
    std::copy(prev + j - 1, prev + j + count, tail_prev);                                             \
    std::copy(score + j, score + j + count, tail_score);                                              \
    SEQTOPO_ROW_VECTOR(W, tail_prev, tail_score)                                                      \
    W::store(tail_out, x);                                                                            \
    std::copy(tail_out, tail_out + count, cur + j);                                                   \
    for (std::size_t k = 0; column_max && k < count; ++k) {                                           \
      column_max[j + k] = std::max(column_max[j + k], tail_out[k]);                                   \
    }                                                                                                 \
    /* lanes past hi were computed from zeros: they must not reach best */                            \
    best = W::max(best, W::set1(*std::max_element(tail_out, tail_out + count)));                      \
  }                                                                                                   \
  return static_cast<std::int16_t>(W::hmax(best));

[[gnu::target("sse4.1")]] std::int16_t row_sse41(const RowJob& job) { SEQTOPO_ROW_KERNEL(Sse41) }
[[gnu::target("avx2")]] std::int16_t row_avx2(const RowJob& job) { SEQTOPO_ROW_KERNEL(Avx2) }

#undef SEQTOPO_ROW_KERNEL
#undef SEQTOPO_ROW_VECTOR

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
void quantize_sse41(const float* in, std::size_t count, float scale, std::int16_t* out) {
  quantize_scalar(in, count, scale, out);
}
void quantize_avx2(const float* in, std::size_t count, float scale, std::int16_t* out) {
  quantize_scalar(in, count, scale, out);
}
}  // namespace seqtopo::align::detail
#endif
