#include "seqtopo/baseline/seqslam.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

#include "seqtopo/similarity/contrast_enhancement.hpp"

namespace seqtopo::baseline {

namespace {

struct Lines {
  const std::vector<std::vector<std::ptrdiff_t>>& offset;  // [velocity][step]: column shift of row q - step
  const std::vector<std::vector<std::ptrdiff_t>>& first;   // [velocity][step]: first column that step reaches
  std::size_t length;
  bool self;
  std::size_t min_separation;
  static constexpr std::size_t max_velocities = 64;
};

// The best line ending at query q. Columns go sixteen at a time, their sums in registers (GCC vector
// extensions: per lane the IEEE operations of the definition's loop, steps in order, from 0), each
// column's count is the number of steps that reach it; the best is taken over columns, then velocities,
// in the definition's order, so ties go the same way.
[[gnu::target_clones("avx2", "default")]] SequenceMatch best_line(const SimilarityMatrix& e, std::size_t q,
                                                                  const Lines& lines) {
  using F4 = float __attribute__((vector_size(16)));
  using D4 = double __attribute__((vector_size(32)));
  constexpr std::size_t kGroups = 4, kBlock = 4 * kGroups, kMaxVelocities = Lines::max_velocities;
  const std::size_t velocities = lines.offset.size();
  SequenceMatch best{q, 0, 0, false};
  // The sequence ends at query q and runs back over min(length, q + 1) frames.
  const std::size_t steps = std::min(lines.length, q + 1);
  std::size_t last_column = e.cols;
  if (lines.self) last_column = q >= lines.min_separation ? q - lines.min_separation + 1 : 0;
  const auto end = static_cast<std::ptrdiff_t>(last_column);
  float score[kMaxVelocities * kBlock];
  for (std::size_t j0 = 0; j0 < last_column; j0 += kBlock) {
    const std::size_t width = std::min(kBlock, last_column - j0);
    for (std::size_t v = 0; v < velocities; ++v) {
      float* out = score + v * kBlock;
      // Steps that reach the whole block (first[v][k] <= j0; first is non-decreasing in k): the block's
      // common count. A step that reaches only part of it sends the block to the cell-by-cell loop.
      std::size_t full = 0;
      while (full < steps && lines.first[v][full] <= static_cast<std::ptrdiff_t>(j0)) ++full;
      const bool partial =
          full < steps && lines.first[v][full] < std::min(end, static_cast<std::ptrdiff_t>(j0 + width));
      if (width < kBlock || partial) {
        for (std::size_t b = 0; b < width; ++b) {
          const auto j = static_cast<std::ptrdiff_t>(j0 + b);
          double sum = 0;
          std::uint32_t count = 0;
          for (std::size_t k = 0; k < steps && lines.first[v][k] <= j; ++k, ++count)
            sum += static_cast<double>(e.row(q - k)[static_cast<std::size_t>(j - lines.offset[v][k])]);
          out[b] = static_cast<float>(sum / static_cast<double>(count));
        }
        continue;
      }
      D4 sum[kGroups] = {};
      for (std::size_t k = 0; k < full; ++k) {
        // offset <= first <= j0, so the block's cells of row q - k start at j0 - offset >= 0
        const float* row = e.row(q - k).data() + (j0 - static_cast<std::size_t>(lines.offset[v][k]));
        for (std::size_t g = 0; g < kGroups; ++g) {
          F4 f;
          std::memcpy(&f, row + 4 * g, sizeof(f));
          sum[g] += __builtin_convertvector(f, D4);
        }
      }
      const double count = static_cast<double>(full);
      for (std::size_t g = 0; g < kGroups; ++g) {
        const F4 f = __builtin_convertvector(sum[g] / count, F4);
        std::memcpy(out + 4 * g, &f, sizeof(f));
      }
    }
    // The definition's scan (columns, then velocities, strictly better) changes nothing unless some score of
    // the block beats the best so far: that is checked first, in vectors.
    if (best.valid && width == kBlock) {
      F4 top = {best.score, best.score, best.score, best.score};
      for (std::size_t k = 0; k < velocities * kBlock; k += 4) {
        F4 f;
        std::memcpy(&f, score + k, sizeof(f));
        top = f > top ? f : top;
      }
      bool better = false;
      for (int l = 0; l < 4; ++l) better = better || top[l] > best.score;
      if (!better) continue;
    }
    for (std::size_t b = 0; b < width; ++b) {
      for (std::size_t v = 0; v < velocities; ++v) {
        if (!best.valid || score[v * kBlock + b] > best.score) best = {q, j0 + b, score[v * kBlock + b], true};
      }
    }
  }
  return best;
}

}  // namespace

std::vector<SequenceMatch> seqslam_matches(const SimilarityMatrix& similarity, const SeqSlamConfig& config) {
  if (config.sequence_length == 0) throw std::invalid_argument("sequence_length must be >= 1");
  if (!(config.min_velocity > 0) || config.max_velocity < config.min_velocity || config.velocity_steps == 0) {
    throw std::invalid_argument("velocities must satisfy 0 < min <= max, with at least one step");
  }
  if (config.velocity_steps > Lines::max_velocities) {
    throw std::invalid_argument("velocity_steps must be at most " + std::to_string(Lines::max_velocities));
  }
  if (config.self && !similarity.square()) throw std::invalid_argument("self mode needs a square similarity matrix");
  std::vector<float> velocities;
  for (std::size_t v = 0; v < config.velocity_steps; ++v) {
    const float t =
        config.velocity_steps == 1 ? 0.0F : static_cast<float>(v) / static_cast<float>(config.velocity_steps - 1);
    velocities.push_back(config.min_velocity + t * (config.max_velocity - config.min_velocity));
  }
  const std::size_t len = config.sequence_length;
  // The line ending at (q, j) with velocity v visits column round(j - v k) of row q - k (halves rounded up), which
  // is column j - ceil(v k - 1/2): one offset per velocity and step, the same for every j, so each step adds a
  // shifted row to the sums of all columns at once. It stops at the first step whose column would be negative,
  // j < v k. Sums run over the steps in order, as the definition's loop does, so the scores are the same.
  std::vector<std::vector<std::ptrdiff_t>> offset(velocities.size()), first(velocities.size());
  for (std::size_t v = 0; v < velocities.size(); ++v) {
    for (std::size_t k = 0; k < len; ++k) {
      const double x = static_cast<double>(velocities[v]) * static_cast<double>(k);
      offset[v].push_back(static_cast<std::ptrdiff_t>(std::ceil(x - 0.5)));
      first[v].push_back(static_cast<std::ptrdiff_t>(std::ceil(x)));
    }
  }
  std::vector<SequenceMatch> out(similarity.rows);
  const int threads = config.threads == 0 ? omp_get_max_threads() : static_cast<int>(config.threads);
  // In self mode the lines ending at q read columns j - offset <= j <= q - min_separation of rows q - k, k < len:
  // row r is read only before column r + len - min_separation, so only that prefix is enhanced (the same bits).
  const SimilarityMatrix* e = &similarity;
  SimilarityMatrix enhanced;
  if (config.contrast_window > 0) {
    enhanced = SimilarityMatrix(similarity.rows, similarity.cols);
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads)
    for (long ri = 0; ri < static_cast<long>(similarity.rows); ++ri) {
      const auto r = static_cast<std::size_t>(ri);
      std::size_t end = similarity.cols;
      if (config.self) end = std::min(end, r + len > config.min_separation ? r + len - config.min_separation : 0);
      similarity::enhance_row_prefix(similarity.row(r).data(), similarity.cols, config.contrast_window, end,
                                     enhanced.row(r).data());
    }
    e = &enhanced;
  }
  const Lines lines{offset, first, len, config.self, config.min_separation};
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads)
  for (long qi = 0; qi < static_cast<long>(similarity.rows); ++qi) {
    out[static_cast<std::size_t>(qi)] = best_line(*e, static_cast<std::size_t>(qi), lines);
  }
  return out;
}

}  // namespace seqtopo::baseline
