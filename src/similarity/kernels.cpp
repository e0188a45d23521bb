#include "kernels.hpp"

#include <algorithm>
#include <cmath>

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

template <SparseSum kind>
inline float sparse_term(float x, float y) {
  if constexpr (kind == SparseSum::chi2) {
    const float d = x - y;
    return d * d / (x + y) - x;
  } else if constexpr (kind == SparseSum::l1) {
    return std::fabs(x - y) - x;
  } else {
    return x * y;
  }
}

template <SparseSum kind>
inline void rows_pass(const float* a8, const std::uint32_t* bins, const float* values, std::size_t n,
                      double (&out)[kRows]) {
  double total[kRows] = {};
  for (std::size_t k = 0; k < n;) {
    float block[kRows] = {};
    const std::size_t end = std::min(n, k + kBlock);
    for (; k < end; ++k) {
      const float* x = a8 + static_cast<std::size_t>(bins[k]) * kRows;
      const float y = values[k];
#pragma omp simd
      for (std::size_t r = 0; r < kRows; ++r) block[r] += sparse_term<kind>(x[r], y);
    }
#pragma omp simd
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
