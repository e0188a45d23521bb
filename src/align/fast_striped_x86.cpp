// The fill's striped kernels (fast_kernels.hpp: StripedJob; the body is fast_striped_body.hpp): SSE4.1
// and AVX2, int16 and int8 lanes, compiled for their instruction set through function attributes and
// chosen at run time. Each traits type gives the body its vector type and the handful of operations it
// uses; saturating arithmetic everywhere, so values below 0 clip harmlessly (every H >= 0).
#include <algorithm>

#include "fast_kernels.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>

namespace seqtopo::align::detail {
namespace {

#define SEQTOPO_SSE41 [[gnu::target("sse4.1"), gnu::always_inline]] static inline
#define SEQTOPO_AVX2 [[gnu::target("avx2"), gnu::always_inline]] static inline

// Largest of values >= 0 in int16 lanes: 32767 minus the unsigned minimum of 32767 - v.
SEQTOPO_SSE41 int hmax16(__m128i v) {
  return 32767 - _mm_extract_epi16(_mm_minpos_epu16(_mm_sub_epi16(_mm_set1_epi16(32767), v)), 0);
}

// What every traits type gives the body:
//  * E, V, kLanes; a value H in [0, kMax] is held as rep(H) = H - kOffset: int16 lanes hold H itself,
//    int8 lanes H - 128, so that [0, 255] fits and signed saturation at -128 is exactly the floor at
//    H = 0 (every H >= 0, so clipping there changes nothing);
//  * zero(): rep(0) in every lane; set1(x): x in every lane (a rep, or a gap for floor_sub);
//  * adds, subs, max, min, cmpgt: signed saturating, on reps (order-preserving);
//  * floor_sub(h, g): rep(max(0, H - g)) for a gap 0 <= g <= kStep;
//  * shift_up(x, first): lane l <- lane l - 1, lane 0 <- first (a rep);
//  * to_h(x), from_h(u): reps to H itself in unsigned lanes and back (int16: nothing to do); on those,
//    usub(u, d) = max(0, u - d) for any d <= kMax, umax, and shift<K>(u): lanes move up by K, 0 (H = 0)
//    into lanes < K;
//  * select(m, a, b), any(m), lane_index() (lane numbers, for comparisons with small ints);
//  * widen_store(out, x), widen_max(acc, x): int16 values H of the lanes (stored, or maxed into acc);
//    hmax(x): the largest H;
//  * int16 lanes only: widen_scores(p), kLanes int8 scores at p sign-extended to int16.

struct Sse41x16 {
  using E = std::int16_t;
  using V = __m128i;
  static constexpr std::size_t kLanes = 8;
  static constexpr int kMax = 32767, kStep = 32767, kOffset = 0;
  SEQTOPO_SSE41 V load(const E* p) { return _mm_loadu_si128(reinterpret_cast<const V*>(p)); }
  SEQTOPO_SSE41 void store(E* p, V v) { _mm_storeu_si128(reinterpret_cast<V*>(p), v); }
  SEQTOPO_SSE41 V set1(int v) { return _mm_set1_epi16(static_cast<std::int16_t>(v)); }
  SEQTOPO_SSE41 V zero() { return _mm_setzero_si128(); }
  SEQTOPO_SSE41 V adds(V a, V b) { return _mm_adds_epi16(a, b); }
  SEQTOPO_SSE41 V subs(V a, V b) { return _mm_subs_epi16(a, b); }
  SEQTOPO_SSE41 V floor_sub(V h, V g) { return _mm_subs_epu16(h, g); }  // h, g >= 0
  SEQTOPO_SSE41 V max(V a, V b) { return _mm_max_epi16(a, b); }
  SEQTOPO_SSE41 V min(V a, V b) { return _mm_min_epi16(a, b); }
  SEQTOPO_SSE41 V cmpgt(V a, V b) { return _mm_cmpgt_epi16(a, b); }
  SEQTOPO_SSE41 V select(V m, V a, V b) { return _mm_blendv_epi8(b, a, m); }
  SEQTOPO_SSE41 bool any(V m) { return !_mm_testz_si128(m, m); }
  SEQTOPO_SSE41 V shift_up(V x, int first) { return _mm_insert_epi16(_mm_slli_si128(x, 2), first, 0); }
  SEQTOPO_SSE41 V to_h(V x) { return x; }
  SEQTOPO_SSE41 V from_h(V u) { return u; }
  SEQTOPO_SSE41 V usub(V u, V d) { return _mm_subs_epu16(u, d); }
  SEQTOPO_SSE41 V umax(V a, V b) { return _mm_max_epu16(a, b); }
  template <int K>
  SEQTOPO_SSE41 V shift(V u) {
    return _mm_slli_si128(u, 2 * K);
  }
  SEQTOPO_SSE41 V lane_index() { return _mm_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7); }
  SEQTOPO_SSE41 void widen_store(std::int16_t* out, V v) { store(out, v); }
  SEQTOPO_SSE41 void widen_max(std::int16_t* acc, V v) { store(acc, max(load(acc), v)); }
  SEQTOPO_SSE41 int hmax(V v) { return hmax16(v); }
  SEQTOPO_SSE41 V widen_scores(const std::int8_t* p) {
    return _mm_cvtepi8_epi16(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)));
  }
};

struct Sse41x8 {
  using E = std::int8_t;
  using V = __m128i;
  static constexpr std::size_t kLanes = 16;
  static constexpr int kMax = 255, kStep = 127, kOffset = 128;
  SEQTOPO_SSE41 V load(const E* p) { return _mm_loadu_si128(reinterpret_cast<const V*>(p)); }
  SEQTOPO_SSE41 void store(E* p, V v) { _mm_storeu_si128(reinterpret_cast<V*>(p), v); }
  SEQTOPO_SSE41 V set1(int v) { return _mm_set1_epi8(static_cast<char>(v)); }
  SEQTOPO_SSE41 V zero() { return _mm_set1_epi8(-128); }
  SEQTOPO_SSE41 V adds(V a, V b) { return _mm_adds_epi8(a, b); }
  SEQTOPO_SSE41 V subs(V a, V b) { return _mm_subs_epi8(a, b); }
  SEQTOPO_SSE41 V floor_sub(V h, V g) { return _mm_subs_epi8(h, g); }
  SEQTOPO_SSE41 V max(V a, V b) { return _mm_max_epi8(a, b); }
  SEQTOPO_SSE41 V min(V a, V b) { return _mm_min_epi8(a, b); }
  SEQTOPO_SSE41 V cmpgt(V a, V b) { return _mm_cmpgt_epi8(a, b); }
  SEQTOPO_SSE41 V select(V m, V a, V b) { return _mm_blendv_epi8(b, a, m); }
  SEQTOPO_SSE41 bool any(V m) { return !_mm_testz_si128(m, m); }
  SEQTOPO_SSE41 V shift_up(V x, int first) { return _mm_insert_epi8(_mm_slli_si128(x, 1), first, 0); }
  SEQTOPO_SSE41 V to_h(V x) { return _mm_xor_si128(x, zero()); }  // H - 128 + 128, modulo 256
  SEQTOPO_SSE41 V from_h(V u) { return _mm_xor_si128(u, zero()); }
  SEQTOPO_SSE41 V usub(V u, V d) { return _mm_subs_epu8(u, d); }
  SEQTOPO_SSE41 V umax(V a, V b) { return _mm_max_epu8(a, b); }
  template <int K>
  SEQTOPO_SSE41 V shift(V u) {
    return _mm_slli_si128(u, K);
  }
  SEQTOPO_SSE41 V lane_index() { return _mm_setr_epi8(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15); }
  SEQTOPO_SSE41 V low16(V v) { return _mm_add_epi16(_mm_cvtepi8_epi16(v), _mm_set1_epi16(128)); }
  SEQTOPO_SSE41 V high16(V v) { return low16(_mm_srli_si128(v, 8)); }
  SEQTOPO_SSE41 void widen_store(std::int16_t* out, V v) {
    Sse41x16::store(out, low16(v));
    Sse41x16::store(out + 8, high16(v));
  }
  SEQTOPO_SSE41 void widen_max(std::int16_t* acc, V v) {
    Sse41x16::widen_max(acc, low16(v));
    Sse41x16::widen_max(acc + 8, high16(v));
  }
  SEQTOPO_SSE41 int hmax(V v) { return hmax16(_mm_max_epi16(low16(v), high16(v))); }
};

struct Avx2x16 {
  using E = std::int16_t;
  using V = __m256i;
  static constexpr std::size_t kLanes = 16;
  static constexpr int kMax = 32767, kStep = 32767, kOffset = 0;
  SEQTOPO_AVX2 V load(const E* p) { return _mm256_loadu_si256(reinterpret_cast<const V*>(p)); }
  SEQTOPO_AVX2 void store(E* p, V v) { _mm256_storeu_si256(reinterpret_cast<V*>(p), v); }
  SEQTOPO_AVX2 V set1(int v) { return _mm256_set1_epi16(static_cast<std::int16_t>(v)); }
  SEQTOPO_AVX2 V zero() { return _mm256_setzero_si256(); }
  SEQTOPO_AVX2 V adds(V a, V b) { return _mm256_adds_epi16(a, b); }
  SEQTOPO_AVX2 V subs(V a, V b) { return _mm256_subs_epi16(a, b); }
  SEQTOPO_AVX2 V floor_sub(V h, V g) { return _mm256_subs_epu16(h, g); }
  SEQTOPO_AVX2 V max(V a, V b) { return _mm256_max_epi16(a, b); }
  SEQTOPO_AVX2 V min(V a, V b) { return _mm256_min_epi16(a, b); }
  SEQTOPO_AVX2 V cmpgt(V a, V b) { return _mm256_cmpgt_epi16(a, b); }
  SEQTOPO_AVX2 V select(V m, V a, V b) { return _mm256_blendv_epi8(b, a, m); }
  SEQTOPO_AVX2 bool any(V m) { return !_mm256_testz_si256(m, m); }
  // (0, low half) then a byte alignment across the halves: every lane moves up
  template <int K>
  SEQTOPO_AVX2 V shift(V u) {
    const V low_up = _mm256_permute2x128_si256(u, u, 0x08);
    if constexpr (K == 8) {
      return low_up;
    } else {
      return _mm256_alignr_epi8(u, low_up, 16 - 2 * K);
    }
  }
  SEQTOPO_AVX2 V shift_up(V x, int first) { return _mm256_insert_epi16(shift<1>(x), first, 0); }
  SEQTOPO_AVX2 V to_h(V x) { return x; }
  SEQTOPO_AVX2 V from_h(V u) { return u; }
  SEQTOPO_AVX2 V usub(V u, V d) { return _mm256_subs_epu16(u, d); }
  SEQTOPO_AVX2 V umax(V a, V b) { return _mm256_max_epu16(a, b); }
  SEQTOPO_AVX2 V lane_index() { return _mm256_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15); }
  SEQTOPO_AVX2 void widen_store(std::int16_t* out, V v) { store(out, v); }
  SEQTOPO_AVX2 void widen_max(std::int16_t* acc, V v) { store(acc, max(load(acc), v)); }
  SEQTOPO_AVX2 int hmax(V v) {
    return hmax16(_mm_max_epi16(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1)));
  }
  SEQTOPO_AVX2 V widen_scores(const std::int8_t* p) {
    return _mm256_cvtepi8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
  }
};

struct Avx2x8 {
  using E = std::int8_t;
  using V = __m256i;
  static constexpr std::size_t kLanes = 32;
  static constexpr int kMax = 255, kStep = 127, kOffset = 128;
  SEQTOPO_AVX2 V load(const E* p) { return _mm256_loadu_si256(reinterpret_cast<const V*>(p)); }
  SEQTOPO_AVX2 void store(E* p, V v) { _mm256_storeu_si256(reinterpret_cast<V*>(p), v); }
  SEQTOPO_AVX2 V set1(int v) { return _mm256_set1_epi8(static_cast<char>(v)); }
  SEQTOPO_AVX2 V zero() { return _mm256_set1_epi8(-128); }
  SEQTOPO_AVX2 V adds(V a, V b) { return _mm256_adds_epi8(a, b); }
  SEQTOPO_AVX2 V subs(V a, V b) { return _mm256_subs_epi8(a, b); }
  SEQTOPO_AVX2 V floor_sub(V h, V g) { return _mm256_subs_epi8(h, g); }
  SEQTOPO_AVX2 V max(V a, V b) { return _mm256_max_epi8(a, b); }
  SEQTOPO_AVX2 V min(V a, V b) { return _mm256_min_epi8(a, b); }
  SEQTOPO_AVX2 V cmpgt(V a, V b) { return _mm256_cmpgt_epi8(a, b); }
  SEQTOPO_AVX2 V select(V m, V a, V b) { return _mm256_blendv_epi8(b, a, m); }
  SEQTOPO_AVX2 bool any(V m) { return !_mm256_testz_si256(m, m); }
  template <int K>
  SEQTOPO_AVX2 V shift(V u) {
    const V low_up = _mm256_permute2x128_si256(u, u, 0x08);
    if constexpr (K == 16) {
      return low_up;
    } else {
      return _mm256_alignr_epi8(u, low_up, 16 - K);
    }
  }
  SEQTOPO_AVX2 V shift_up(V x, int first) { return _mm256_insert_epi8(shift<1>(x), first, 0); }
  SEQTOPO_AVX2 V to_h(V x) { return _mm256_xor_si256(x, zero()); }
  SEQTOPO_AVX2 V from_h(V u) { return _mm256_xor_si256(u, zero()); }
  SEQTOPO_AVX2 V usub(V u, V d) { return _mm256_subs_epu8(u, d); }
  SEQTOPO_AVX2 V umax(V a, V b) { return _mm256_max_epu8(a, b); }
  SEQTOPO_AVX2 V lane_index() {
    return _mm256_setr_epi8(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24,
                            25, 26, 27, 28, 29, 30, 31);
  }
  SEQTOPO_AVX2 V low16(V v) {
    return _mm256_add_epi16(_mm256_cvtepi8_epi16(_mm256_castsi256_si128(v)), _mm256_set1_epi16(128));
  }
  SEQTOPO_AVX2 V high16(V v) {
    return _mm256_add_epi16(_mm256_cvtepi8_epi16(_mm256_extracti128_si256(v, 1)), _mm256_set1_epi16(128));
  }
  SEQTOPO_AVX2 void widen_store(std::int16_t* out, V v) {
    Avx2x16::store(out, low16(v));
    Avx2x16::store(out + 16, high16(v));
  }
  SEQTOPO_AVX2 void widen_max(std::int16_t* acc, V v) {
    Avx2x16::widen_max(acc, low16(v));
    Avx2x16::widen_max(acc + 16, high16(v));
  }
  SEQTOPO_AVX2 int hmax(V v) { return Avx2x16::hmax(_mm256_max_epi16(low16(v), high16(v))); }
};

// Transposes 8 x 8 int16 in each 128-bit half of a[0..7] (a[r] = row r): a[c] becomes column c. A macro
// over the unpack operations of the struct it is expanded in (a template would lose the target).
#define SEQTOPO_TRANSPOSE8                                                                            \
  const V b0 = lo16(a[0], a[1]), b1 = hi16(a[0], a[1]), b2 = lo16(a[2], a[3]), b3 = hi16(a[2], a[3]); \
  const V b4 = lo16(a[4], a[5]), b5 = hi16(a[4], a[5]), b6 = lo16(a[6], a[7]), b7 = hi16(a[6], a[7]); \
  const V c0 = lo32(b0, b2), c1 = hi32(b0, b2), c2 = lo32(b1, b3), c3 = hi32(b1, b3);                 \
  const V c4 = lo32(b4, b6), c5 = hi32(b4, b6), c6 = lo32(b5, b7), c7 = hi32(b5, b7);                 \
  a[0] = lo64(c0, c4);                                                                                \
  a[1] = hi64(c0, c4);                                                                                \
  a[2] = lo64(c1, c5);                                                                                \
  a[3] = hi64(c1, c5);                                                                                \
  a[4] = lo64(c2, c6);                                                                                \
  a[5] = hi64(c2, c6);                                                                                \
  a[6] = lo64(c3, c7);                                                                                \
  a[7] = hi64(c3, c7);

struct SseUnpack {
  using V = __m128i;
  SEQTOPO_SSE41 V lo16(V a, V b) { return _mm_unpacklo_epi16(a, b); }
  SEQTOPO_SSE41 V hi16(V a, V b) { return _mm_unpackhi_epi16(a, b); }
  SEQTOPO_SSE41 V lo32(V a, V b) { return _mm_unpacklo_epi32(a, b); }
  SEQTOPO_SSE41 V hi32(V a, V b) { return _mm_unpackhi_epi32(a, b); }
  SEQTOPO_SSE41 V lo64(V a, V b) { return _mm_unpacklo_epi64(a, b); }
  SEQTOPO_SSE41 V hi64(V a, V b) { return _mm_unpackhi_epi64(a, b); }
  SEQTOPO_SSE41 void transpose8(V* a) { SEQTOPO_TRANSPOSE8 }
};
struct AvxUnpack {
  using V = __m256i;
  SEQTOPO_AVX2 V lo16(V a, V b) { return _mm256_unpacklo_epi16(a, b); }
  SEQTOPO_AVX2 V hi16(V a, V b) { return _mm256_unpackhi_epi16(a, b); }
  SEQTOPO_AVX2 V lo32(V a, V b) { return _mm256_unpacklo_epi32(a, b); }
  SEQTOPO_AVX2 V hi32(V a, V b) { return _mm256_unpackhi_epi32(a, b); }
  SEQTOPO_AVX2 V lo64(V a, V b) { return _mm256_unpacklo_epi64(a, b); }
  SEQTOPO_AVX2 V hi64(V a, V b) { return _mm256_unpackhi_epi64(a, b); }
  SEQTOPO_AVX2 void transpose8(V* a) { SEQTOPO_TRANSPOSE8 }
};
#undef SEQTOPO_TRANSPOSE8
#undef SEQTOPO_SSE41
#undef SEQTOPO_AVX2

// The transpose of 8 x 8 int16 (rows at in + r * stride): out[c] = column c.
[[gnu::target("sse4.1")]] inline void transpose8_sse41(const std::int16_t* in, std::size_t stride, __m128i* out) {
  for (std::size_t r = 0; r < 8; ++r) out[r] = _mm_loadu_si128(reinterpret_cast<const __m128i*>(in + r * stride));
  SseUnpack::transpose8(out);
}

// The transpose of 16 x 16 int16, as four 8 x 8 (rows r and r + 8 share a vector).
[[gnu::target("avx2")]] inline void transpose16_avx2(const std::int16_t* in, std::size_t stride, __m256i* out) {
  __m256i r[16];
  for (std::size_t t = 0; t < 16; ++t) r[t] = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(in + t * stride));
  for (std::size_t t = 0; t < 8; ++t) {  // low halves: columns 0-7, high halves: 8-15; rows t and t + 8
    out[t] = _mm256_permute2x128_si256(r[t], r[t + 8], 0x20);
    out[t + 8] = _mm256_permute2x128_si256(r[t], r[t + 8], 0x31);
  }
  AvxUnpack::transpose8(out);
  AvxUnpack::transpose8(out + 8);
}

// A striped int16 block of `lanes` tiles (vector s at in + s * lanes) into natural order, the tile of
// lane l at out + 32 l: its transpose, `lanes` x `lanes` at a time.
[[gnu::target("sse4.1")]] inline void destripe_lanes8_sse41(const std::int16_t* in, std::int16_t* out) {
  __m128i c[8];
  for (std::size_t s0 = 0; s0 < kTileSide; s0 += 8) {
    transpose8_sse41(in + s0 * 8, 8, c);
    for (std::size_t l = 0; l < 8; ++l) _mm_storeu_si128(reinterpret_cast<__m128i*>(out + kTileSide * l + s0), c[l]);
  }
}
[[gnu::target("avx2")]] inline void destripe_lanes16_avx2(const std::int16_t* in, std::int16_t* out) {
  __m256i c[16];
  for (std::size_t s0 = 0; s0 < kTileSide; s0 += 16) {
    transpose16_avx2(in + s0 * 16, 16, c);
    for (std::size_t l = 0; l < 16; ++l) {
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + kTileSide * l + s0), c[l]);
    }
  }
}

namespace sse41 {
#define SEQTOPO_STRIPED_ISA "sse4.1"
#include "fast_striped_body.hpp"
#undef SEQTOPO_STRIPED_ISA
}  // namespace sse41

namespace avx2 {
#define SEQTOPO_STRIPED_ISA "avx2"
#include "fast_striped_body.hpp"
#undef SEQTOPO_STRIPED_ISA
}  // namespace avx2

}  // namespace

// Natural scores of one block -> its striped layout (striped_index): out[s * lanes + l] = in[32 l + s].
[[gnu::target("sse4.1")]] void stripe16_sse41(const std::int16_t* in, std::int16_t* out) {
  __m128i c[8];
  for (std::size_t c0 = 0; c0 < kTileSide; c0 += 8) {
    transpose8_sse41(in + c0, kTileSide, c);
    for (std::size_t s = 0; s < 8; ++s) _mm_storeu_si128(reinterpret_cast<__m128i*>(out + (c0 + s) * 8), c[s]);
  }
}
[[gnu::target("sse4.1")]] void stripe8_sse41(const std::int16_t* in, std::int8_t* out) {
  __m128i a[8], b[8];
  for (std::size_t c0 = 0; c0 < kTileSide; c0 += 8) {
    transpose8_sse41(in + c0, kTileSide, a);
    transpose8_sse41(in + 8 * kTileSide + c0, kTileSide, b);
    for (std::size_t s = 0; s < 8; ++s) {
      _mm_storeu_si128(reinterpret_cast<__m128i*>(out + (c0 + s) * 16), _mm_packs_epi16(a[s], b[s]));
    }
  }
}
[[gnu::target("avx2")]] void stripe16_avx2(const std::int16_t* in, std::int16_t* out) {
  __m256i c[16];
  for (std::size_t c0 = 0; c0 < kTileSide; c0 += 16) {
    transpose16_avx2(in + c0, kTileSide, c);
    for (std::size_t s = 0; s < 16; ++s) _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + (c0 + s) * 16), c[s]);
  }
}
[[gnu::target("avx2")]] void stripe8_avx2(const std::int16_t* in, std::int8_t* out) {
  __m256i a[16], b[16];
  for (std::size_t c0 = 0; c0 < kTileSide; c0 += 16) {
    transpose16_avx2(in + c0, kTileSide, a);
    transpose16_avx2(in + 16 * kTileSide + c0, kTileSide, b);
    for (std::size_t s = 0; s < 16; ++s) {  // packs works per half: tiles 0-7, 16-23 | 8-15, 24-31
      const __m256i packed = _mm256_permute4x64_epi64(_mm256_packs_epi16(a[s], b[s]), 0xD8);
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + (c0 + s) * 32), packed);
    }
  }
}

// One striped block back into natural order, as H (int8 rows hold H - 128): out[32 l + s] = in[s * lanes + l].
[[gnu::target("sse4.1")]] void destripe16_sse41(const std::int16_t* in, std::int16_t* out) {
  destripe_lanes8_sse41(in, out);
}
[[gnu::target("sse4.1")]] void destripe8_sse41(const std::int8_t* in, std::int16_t* out) {
  alignas(16) std::int16_t half[2][kTileSide * 8];  // lanes 0-7 and 8-15, widened
  for (std::size_t s = 0; s < kTileSide; ++s) {
    const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(in + s * 16));
    _mm_store_si128(reinterpret_cast<__m128i*>(half[0] + s * 8), Sse41x8::low16(v));
    _mm_store_si128(reinterpret_cast<__m128i*>(half[1] + s * 8), Sse41x8::high16(v));
  }
  destripe_lanes8_sse41(half[0], out);
  destripe_lanes8_sse41(half[1], out + 8 * kTileSide);
}
[[gnu::target("avx2")]] void destripe16_avx2(const std::int16_t* in, std::int16_t* out) {
  destripe_lanes16_avx2(in, out);
}
[[gnu::target("avx2")]] void destripe8_avx2(const std::int8_t* in, std::int16_t* out) {
  alignas(32) std::int16_t half[2][kTileSide * 16];  // lanes 0-15 and 16-31, widened
  for (std::size_t s = 0; s < kTileSide; ++s) {
    const __m256i v = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(in + s * 32));
    _mm256_store_si256(reinterpret_cast<__m256i*>(half[0] + s * 16), Avx2x8::low16(v));
    _mm256_store_si256(reinterpret_cast<__m256i*>(half[1] + s * 16), Avx2x8::high16(v));
  }
  destripe_lanes16_avx2(half[0], out);
  destripe_lanes16_avx2(half[1], out + 16 * kTileSide);
}

[[gnu::target("sse4.1")]] std::int16_t striped16_sse41(const StripedJob& job) {
  return sse41::striped_row<Sse41x16>(job);
}
[[gnu::target("sse4.1")]] std::int16_t striped8_sse41(const StripedJob& job) {
  return sse41::striped_row<Sse41x8>(job);
}
[[gnu::target("avx2")]] std::int16_t striped16_avx2(const StripedJob& job) { return avx2::striped_row<Avx2x16>(job); }
[[gnu::target("avx2")]] std::int16_t striped8_avx2(const StripedJob& job) { return avx2::striped_row<Avx2x8>(job); }

}  // namespace seqtopo::align::detail

#else
// Other CPUs: best_isa() reports scalar and the fill never asks for these; they exist so the tables link.
#include <stdexcept>

namespace seqtopo::align::detail {
namespace {
std::int16_t unavailable(const StripedJob&) { throw std::logic_error("no striped kernel on this CPU"); }
}  // namespace
std::int16_t striped16_sse41(const StripedJob& job) { return unavailable(job); }
std::int16_t striped8_sse41(const StripedJob& job) { return unavailable(job); }
std::int16_t striped16_avx2(const StripedJob& job) { return unavailable(job); }
std::int16_t striped8_avx2(const StripedJob& job) { return unavailable(job); }
void stripe16_sse41(const std::int16_t*, std::int16_t*) { throw std::logic_error("no striped kernel on this CPU"); }
void stripe8_sse41(const std::int16_t*, std::int8_t*) { throw std::logic_error("no striped kernel on this CPU"); }
void stripe16_avx2(const std::int16_t*, std::int16_t*) { throw std::logic_error("no striped kernel on this CPU"); }
void stripe8_avx2(const std::int16_t*, std::int8_t*) { throw std::logic_error("no striped kernel on this CPU"); }
void destripe16_sse41(const std::int16_t*, std::int16_t*) { throw std::logic_error("no striped kernel on this CPU"); }
void destripe8_sse41(const std::int8_t*, std::int16_t*) { throw std::logic_error("no striped kernel on this CPU"); }
void destripe16_avx2(const std::int16_t*, std::int16_t*) { throw std::logic_error("no striped kernel on this CPU"); }
void destripe8_avx2(const std::int8_t*, std::int16_t*) { throw std::logic_error("no striped kernel on this CPU"); }
}  // namespace seqtopo::align::detail
#endif
