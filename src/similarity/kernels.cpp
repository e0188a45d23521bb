#include "kernels.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

// One copy for AVX2 machines and one for any x86-64, chosen once per process when the program starts, so
// results never mix the two.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define SEQTOPO_KERNEL __attribute__((target_clones("avx2", "default")))
#else
#define SEQTOPO_KERNEL
#endif

namespace seqtopo::similarity::detail {
namespace {

constexpr std::size_t kLanes = 8;

double combine(const double (&l)[kLanes]) { return ((l[0] + l[1]) + (l[2] + l[3])) + ((l[4] + l[5]) + (l[6] + l[7])); }

}  // namespace

SEQTOPO_KERNEL double lane_sum_squares(const float* values, std::size_t n) {
  double s[kLanes] = {};
  std::size_t k = 0;
  for (; k + kLanes <= n; k += kLanes) {
#pragma omp simd
    for (std::size_t l = 0; l < kLanes; ++l)
      s[l] += static_cast<double>(values[k + l]) * static_cast<double>(values[k + l]);
  }
  for (std::size_t l = 0; k < n; ++k, ++l) s[l] += static_cast<double>(values[k]) * static_cast<double>(values[k]);
  return combine(s);
}

namespace {

constexpr std::size_t kBlock = 64;  // bins summed in float before the partial sum goes to double

// Eight rows in one vector (GCC vector extensions: the same IEEE operation on each lane, so the same result
// as the scalar expression; the compiler's own vectorisation of the plain loop fell back to scalar code).
using Lanes = float __attribute__((vector_size(kRows * sizeof(float))));
using Bits = std::uint32_t __attribute__((vector_size(kRows * sizeof(float))));

template <SparseSum kind>
inline void rows_pass(const float* a8, const std::uint32_t* bins, const float* values, std::size_t n,
                      double (&out)[kRows]) {
  double total[kRows] = {};
  for (std::size_t k = 0; k < n;) {
    Lanes block = {};
    const std::size_t end = std::min(n, k + kBlock);
    for (; k < end; ++k) {
      Lanes x;
      std::memcpy(&x, a8 + static_cast<std::size_t>(bins[k]) * kRows, sizeof(x));
      const float y = values[k];
      if constexpr (kind == SparseSum::chi2) {
        const Lanes d = x - y;
        block += d * d / (x + y) - x;
      } else if constexpr (kind == SparseSum::l1) {
        Lanes d = x - y;
        Bits bits;  // |d| as std::fabs: the sign bit cleared
        std::memcpy(&bits, &d, sizeof(d));
        bits &= 0x7fffffff;
        std::memcpy(&d, &bits, sizeof(d));
        block += d - x;
      } else {
        block += x * y;
      }
    }
    for (std::size_t r = 0; r < kRows; ++r) total[r] += static_cast<double>(block[r]);
  }
  for (std::size_t r = 0; r < kRows; ++r) out[r] = total[r];
}

template <typename F>
inline double sequential_sum(std::size_t n, F&& f) {
  double total = 0;
  for (std::size_t k = 0; k < n;) {
    float block = 0;
    const std::size_t end = std::min(n, k + kBlock);
    for (; k < end; ++k) block += f(k);
    total += static_cast<double>(block);
  }
  return total;
}

}  // namespace

SEQTOPO_KERNEL void sparse_sums(SparseSum kind, const float* a8, const std::uint32_t* bins, const float* values,
                                std::size_t n, double (&out)[kRows]) {
  switch (kind) {
    case SparseSum::chi2:
      rows_pass<SparseSum::chi2>(a8, bins, values, n, out);
      break;
    case SparseSum::l1:
      rows_pass<SparseSum::l1>(a8, bins, values, n, out);
      break;
    case SparseSum::dot:
      rows_pass<SparseSum::dot>(a8, bins, values, n, out);
      break;
  }
}

double sparse_sum(const float* values, std::size_t n) {
  return sequential_sum(n, [values](std::size_t k) { return values[k]; });
}

double sparse_sum_squares(const float* values, std::size_t n) {
  return sequential_sum(n, [values](std::size_t k) { return values[k] * values[k]; });
}

namespace {

inline float dense_chi2_term(float x, float y) {
  const float den = x + y;
  const float d = x - y;
  return den > 0.0F ? d * d / den : 0.0F;  // 0/0 terms are skipped (paper eq. 1)
}

}  // namespace

SEQTOPO_KERNEL double dense_chi2(const float* a, const float* b, std::size_t n) {
  double s[kLanes] = {};
  std::size_t k = 0;
  for (; k + kLanes <= n; k += kLanes) {
#pragma omp simd
    for (std::size_t l = 0; l < kLanes; ++l) s[l] += static_cast<double>(dense_chi2_term(a[k + l], b[k + l]));
  }
  for (std::size_t l = 0; k < n; ++k, ++l) s[l] += static_cast<double>(dense_chi2_term(a[k], b[k]));
  return combine(s);
}

SEQTOPO_KERNEL double dense_l1(const float* a, const float* b, std::size_t n) {
  double s[kLanes] = {};
  std::size_t k = 0;
  for (; k + kLanes <= n; k += kLanes) {
#pragma omp simd
    for (std::size_t l = 0; l < kLanes; ++l) s[l] += static_cast<double>(std::fabs(a[k + l] - b[k + l]));
  }
  for (std::size_t l = 0; k < n; ++k, ++l) s[l] += static_cast<double>(std::fabs(a[k] - b[k]));
  return combine(s);
}

SEQTOPO_KERNEL double dense_dot(const float* a, const float* b, std::size_t n) {
  double s[kLanes] = {};
  std::size_t k = 0;
  for (; k + kLanes <= n; k += kLanes) {
#pragma omp simd
    for (std::size_t l = 0; l < kLanes; ++l) s[l] += static_cast<double>(a[k + l]) * static_cast<double>(b[k + l]);
  }
  for (std::size_t l = 0; k < n; ++k, ++l) s[l] += static_cast<double>(a[k]) * static_cast<double>(b[k]);
  return combine(s);
}

double cosine_from_dot(double dot, double norm2_a, double norm2_b) {
  if (norm2_a == 0.0 && norm2_b == 0.0) return 0.0;
  if (norm2_a == 0.0 || norm2_b == 0.0) return 1.0;
  const double d = 1.0 - dot / std::sqrt(norm2_a * norm2_b);
  return d < 0.0 ? 0.0 : (d > 2.0 ? 2.0 : d);
}

}  // namespace seqtopo::similarity::detail

namespace seqtopo::similarity::detail {

bool on_byte_grid(const float* values, std::size_t n, int shift) {
  const float scale = std::ldexp(1.0F, shift);
  for (std::size_t k = 0; k < n; ++k) {
    const float q = values[k] * scale;  // exact: a power of two
    if (!(std::fabs(q) <= 127.0F) || q != std::nearbyint(q)) return false;
  }
  return true;
}

void to_bytes(const float* values, std::size_t n, int shift, std::uint8_t* out) {
  const float scale = std::ldexp(1.0F, shift);
  for (std::size_t k = 0; k < n; ++k) out[k] = static_cast<std::uint8_t>(static_cast<int>(values[k] * scale) + 128);
}

std::uint64_t byte_l1(const std::uint8_t* a, const std::uint8_t* b, std::size_t n) {
  std::uint64_t s = 0;
  for (std::size_t k = 0; k < n; ++k) s += static_cast<std::uint64_t>(a[k] > b[k] ? a[k] - b[k] : b[k] - a[k]);
  return s;
}

#if defined(__x86_64__) && defined(__GNUC__)
namespace {

// Integer sums: any order gives the same result, so the two versions need not agree on one.
__attribute__((target("avx2"))) void byte_l1_4_avx2(const std::uint8_t* a, const std::uint8_t* const (&b)[4],
                                                    std::size_t n, std::uint64_t (&out)[4]) {
  __m256i s0 = _mm256_setzero_si256(), s1 = s0, s2 = s0, s3 = s0;
  std::size_t k = 0;
  for (; k + 32 <= n; k += 32) {
    const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(a + k));
    s0 = _mm256_add_epi64(s0, _mm256_sad_epu8(x, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b[0] + k))));
    s1 = _mm256_add_epi64(s1, _mm256_sad_epu8(x, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b[1] + k))));
    s2 = _mm256_add_epi64(s2, _mm256_sad_epu8(x, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b[2] + k))));
    s3 = _mm256_add_epi64(s3, _mm256_sad_epu8(x, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b[3] + k))));
  }
  const __m256i* sums[4] = {&s0, &s1, &s2, &s3};
  for (int c = 0; c < 4; ++c) {
    alignas(32) std::uint64_t lanes[4];
    _mm256_store_si256(reinterpret_cast<__m256i*>(lanes), *sums[c]);
    out[c] = lanes[0] + lanes[1] + lanes[2] + lanes[3] + byte_l1(a + k, b[c] + k, n - k);
  }
}

void byte_l1_4_sse2(const std::uint8_t* a, const std::uint8_t* const (&b)[4], std::size_t n, std::uint64_t (&out)[4]) {
  __m128i s0 = _mm_setzero_si128(), s1 = s0, s2 = s0, s3 = s0;
  std::size_t k = 0;
  for (; k + 16 <= n; k += 16) {
    const __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(a + k));
    s0 = _mm_add_epi64(s0, _mm_sad_epu8(x, _mm_loadu_si128(reinterpret_cast<const __m128i*>(b[0] + k))));
    s1 = _mm_add_epi64(s1, _mm_sad_epu8(x, _mm_loadu_si128(reinterpret_cast<const __m128i*>(b[1] + k))));
    s2 = _mm_add_epi64(s2, _mm_sad_epu8(x, _mm_loadu_si128(reinterpret_cast<const __m128i*>(b[2] + k))));
    s3 = _mm_add_epi64(s3, _mm_sad_epu8(x, _mm_loadu_si128(reinterpret_cast<const __m128i*>(b[3] + k))));
  }
  const __m128i* sums[4] = {&s0, &s1, &s2, &s3};
  for (int c = 0; c < 4; ++c) {
    alignas(16) std::uint64_t lanes[2];
    _mm_store_si128(reinterpret_cast<__m128i*>(lanes), *sums[c]);
    out[c] = lanes[0] + lanes[1] + byte_l1(a + k, b[c] + k, n - k);
  }
}

}  // namespace
#endif

void byte_l1_4(const std::uint8_t* a, const std::uint8_t* const (&b)[4], std::size_t n, std::uint64_t (&out)[4]) {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2) return byte_l1_4_avx2(a, b, n, out);
  return byte_l1_4_sse2(a, b, n, out);
#else
  for (int c = 0; c < 4; ++c) out[c] = byte_l1(a, b[c], n);
#endif
}

}  // namespace seqtopo::similarity::detail
