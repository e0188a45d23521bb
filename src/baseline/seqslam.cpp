#include "seqtopo/baseline/seqslam.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "seqtopo/similarity/contrast_enhancement.hpp"

namespace seqtopo::baseline {

std::vector<SequenceMatch> seqslam_matches(const SimilarityMatrix& similarity, const SeqSlamConfig& config) {
  if (config.sequence_length == 0) throw std::invalid_argument("sequence_length must be >= 1");
  if (!(config.min_velocity > 0) || config.max_velocity < config.min_velocity || config.velocity_steps == 0) {
    throw std::invalid_argument("velocities must satisfy 0 < min <= max, with at least one step");
  }
  if (config.self && !similarity.square()) throw std::invalid_argument("self mode needs a square similarity matrix");
  const SimilarityMatrix e = similarity::enhance_contrast(similarity, config.contrast_window);
  std::vector<float> velocities;
  for (std::size_t v = 0; v < config.velocity_steps; ++v) {
    const float t =
        config.velocity_steps == 1 ? 0.0F : static_cast<float>(v) / static_cast<float>(config.velocity_steps - 1);
    velocities.push_back(config.min_velocity + t * (config.max_velocity - config.min_velocity));
  }
  const std::size_t len = config.sequence_length, cols = similarity.cols;
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
#pragma omp parallel num_threads(threads)
  {
    std::vector<double> sum(cols);
    std::vector<std::uint32_t> count(cols);
    std::vector<float> score(velocities.size() * cols);
#pragma omp for schedule(dynamic, 16)
    for (long qi = 0; qi < static_cast<long>(similarity.rows); ++qi) {
      const auto q = static_cast<std::size_t>(qi);
      SequenceMatch best{q, 0, 0, false};
      // The sequence ends at query q and runs back over min(len, q + 1) frames.
      const std::size_t steps = std::min(len, q + 1);
      std::size_t last_column = cols;
      if (config.self) last_column = q >= config.min_separation ? q - config.min_separation + 1 : 0;
      const auto end = static_cast<std::ptrdiff_t>(last_column);
      for (std::size_t v = 0; v < velocities.size(); ++v) {
        std::fill(sum.begin(), sum.begin() + end, 0.0);
        std::fill(count.begin(), count.begin() + end, 0U);
        for (std::size_t k = 0; k < steps && first[v][k] < end; ++k) {
          const float* row = e.row(q - k).data();
          const std::ptrdiff_t shift = offset[v][k];
          for (std::ptrdiff_t j = first[v][k]; j < end; ++j) {
            sum[static_cast<std::size_t>(j)] += row[j - shift];
            ++count[static_cast<std::size_t>(j)];
          }
        }
        for (std::size_t j = 0; j < last_column; ++j)
          score[v * cols + j] = static_cast<float>(sum[j] / static_cast<double>(count[j]));
      }
      for (std::size_t j = 0; j < last_column; ++j) {
        for (std::size_t v = 0; v < velocities.size(); ++v) {
          if (!best.valid || score[v * cols + j] > best.score) best = {q, j, score[v * cols + j], true};
        }
      }
      out[q] = best;
    }
  }
  return out;
}

}  // namespace seqtopo::baseline
