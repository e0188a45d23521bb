#include "seqtopo/similarity/contrast_enhancement.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace seqtopo::similarity {

float contrast_score(float v, double sum, double sum2, double count) {
  const double mean = sum / count;
  const double sd = std::sqrt(std::max(0.0, sum2 / count - mean * mean));
  return static_cast<float>((v - mean) / std::max(sd, 1e-9));
}

// Sixteen cells at a time in registers (GCC vector extensions: per lane the same IEEE operations as one
// cell alone), the terms of each cell in order, no fused multiply-add (-ffp-contract=off): the same bits as
// a cell at a time, without storing the sums back after every term.
[[gnu::target_clones("avx2", "default")]] void window_sums(double* sum, double* sum2, const float* first,
                                                           std::size_t stride, std::size_t terms, std::size_t count) {
  using F4 = float __attribute__((vector_size(16)));
  using D4 = double __attribute__((vector_size(32)));
  constexpr std::size_t kGroups = 4, kCells = 4 * kGroups;
  std::size_t b = 0;
  for (; b + kCells <= count; b += kCells) {
    D4 s[kGroups] = {}, q[kGroups] = {};
    for (std::size_t t = 0; t < terms; ++t) {
      const float* v = first + t * stride + b;
      for (std::size_t g = 0; g < kGroups; ++g) {
        F4 f;
        std::memcpy(&f, v + 4 * g, sizeof(f));
        const D4 x = __builtin_convertvector(f, D4);
        s[g] += x;
        q[g] += x * x;
      }
    }
    for (std::size_t g = 0; g < kGroups; ++g) {
      std::memcpy(sum + b + 4 * g, &s[g], sizeof(s[g]));
      std::memcpy(sum2 + b + 4 * g, &q[g], sizeof(q[g]));
    }
  }
  for (; b < count; ++b) {
    double s = 0, q = 0;
    for (std::size_t t = 0; t < terms; ++t) {
      const double x = first[t * stride + b];
      s += x;
      q += x * x;
    }
    sum[b] = s;
    sum2[b] = q;
  }
}

namespace {

// contrast_score of cells [begin, end), whose windows all have `count` cells: a loop the compiler vectorises
// (sqrt and division are correctly rounded in vectors too, so the bits are contrast_score's).
[[gnu::target_clones("avx2", "default")]] void scores(const float* row, const double* sum, const double* sum2,
                                                      double count, std::size_t begin, std::size_t end, float* out) {
  for (std::size_t c = begin; c < end; ++c) {
    const double mean = sum[c] / count;
    const double sd = std::sqrt(std::max(0.0, sum2[c] / count - mean * mean));
    out[c] = static_cast<float>((row[c] - mean) / std::max(sd, 1e-9));
  }
}

}  // namespace

void enhance_row(const float* row, std::size_t cols, std::size_t window, float* out) {
  enhance_row_prefix(row, cols, window, cols, out);
}

std::size_t first_read(std::size_t begin, std::size_t w) {
  const std::size_t start = w >= kRunningWindow ? begin - begin % kRunningBlock : begin;
  return start > w ? start - w : 0;
}

void window_sums_of(double* sum, double* sum2, double* count, const float* x, std::size_t x0, std::size_t n,
                    std::size_t w, std::size_t begin, std::size_t end) {
  if (end > n) throw std::invalid_argument("window sums: cells past the row");
  if (begin >= end) return;
  if (x0 > first_read(begin, w)) throw std::invalid_argument("window sums: the row's values start too late");
  const auto lo = [w](std::size_t c) { return c > w ? c - w : 0; };
  const auto hi = [w, n](std::size_t c) { return std::min(n, c + w + 1); };
  for (std::size_t c = begin; c < end; ++c) count[c - begin] = static_cast<double>(hi(c) - lo(c));
  if (w < kRunningWindow) {
    // Cells whose window is not clipped (c in [w, n - w)) have windows of 2w + 1 values starting one apart: one
    // call sums them all; each clipped cell takes a call of its own.
    std::size_t in_lo = std::max(begin, w), in_hi = std::min(end, n > w ? n - w : 0);
    if (in_hi > in_lo) {
      window_sums(sum + (in_lo - begin), sum2 + (in_lo - begin), x + (in_lo - w - x0), 1, 2 * w + 1, in_hi - in_lo);
    } else {
      in_lo = in_hi = end;
    }
    for (std::size_t c = begin; c < end; ++c) {
      if (c >= in_lo && c < in_hi) continue;
      window_sums(sum + (c - begin), sum2 + (c - begin), x + (lo(c) - x0), 1, hi(c) - lo(c), 1);
    }
    return;
  }
  double s = 0, q = 0;
  for (std::size_t c = begin - begin % kRunningBlock; c < end; ++c) {
    if (c % kRunningBlock == 0) {
      // Term by term, the bits window_sums gives, summed here: its loop for any stride took 6 % of a streamed map.
      s = q = 0;
      for (std::size_t k = lo(c); k < hi(c); ++k) {
        const double v = x[k - x0];
        s += v;
        q += v * v;
      }
    } else {
      running_window_step(&s, &q, c + w < n ? x + (c + w - x0) : nullptr, c > w ? x + (c - w - 1 - x0) : nullptr, 1);
    }
    if (c >= begin) sum[c - begin] = s, sum2[c - begin] = q;
  }
}

void enhance_row_prefix(const float* row, std::size_t cols, std::size_t window, std::size_t end, float* out) {
  if (end > cols) throw std::invalid_argument("enhance_row_prefix: end past the row");
  const std::size_t w = std::min(window, cols);  // a wider window is the whole row
  std::vector<double> sum(end), sum2(end), count(end);
  // Each cell's sums depend on its window and the fixed restarts only, so stopping at `end` changes no bit of the
  // cells before it.
  window_sums_of(sum.data(), sum2.data(), count.data(), row, 0, cols, w, 0, end);
  const std::size_t in_lo = std::min(w, end), in_hi = std::max(in_lo, std::min(end, cols > w ? cols - w : 0));
  for (std::size_t c = 0; c < in_lo; ++c) out[c] = contrast_score(row[c], sum[c], sum2[c], count[c]);
  scores(row, sum.data(), sum2.data(), static_cast<double>(2 * w + 1), in_lo, in_hi, out);
  for (std::size_t c = in_hi; c < end; ++c) out[c] = contrast_score(row[c], sum[c], sum2[c], count[c]);
}

SimilarityMatrix enhance_contrast(const SimilarityMatrix& s, std::size_t window) {
  if (window == 0) return s;
  SimilarityMatrix out(s.rows, s.cols);
  // Each row is independent and summed in a fixed order: identical results for any thread count.
#pragma omp parallel for schedule(static)
  for (long r = 0; r < static_cast<long>(s.rows); ++r) {
    const auto i = static_cast<std::size_t>(r);
    enhance_row(s.row(i).data(), s.cols, window, out.row(i).data());
  }
  return out;
}

SimilarityMatrix enhance_contrast_symmetric(const SimilarityMatrix& s, std::size_t window, float offset) {
  if (!s.square()) throw std::invalid_argument("symmetric contrast enhancement needs a square matrix");
  SimilarityMatrix out = enhance_contrast(s, window);
  // In place, each pair (i, j), (j, i) once (addition commutes, so both get the same bits), in 64 x 64
  // blocks so that the transposed side stays in cache; block rows are independent.
  constexpr std::size_t kBlock = 64;
  const std::size_t n = s.rows;
  const auto blocks = static_cast<long>((n + kBlock - 1) / kBlock);
#pragma omp parallel for schedule(dynamic, 1)
  for (long bi = 0; bi < blocks; ++bi) {
    const std::size_t i0 = static_cast<std::size_t>(bi) * kBlock, i1 = std::min(n, i0 + kBlock);
    for (std::size_t j0 = i0; j0 < n; j0 += kBlock) {
      const std::size_t j1 = std::min(n, j0 + kBlock);
      for (std::size_t i = i0; i < i1; ++i) {
        for (std::size_t j = std::max(j0, i); j < j1; ++j) {
          const float v = 0.5F * (out(i, j) + out(j, i)) - offset;
          out(i, j) = v;
          out(j, i) = v;
        }
      }
    }
  }
  return out;
}

}  // namespace seqtopo::similarity
