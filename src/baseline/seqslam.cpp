#include "seqtopo/baseline/seqslam.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
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
  const std::size_t len = config.sequence_length;
  std::vector<SequenceMatch> out(similarity.rows);
  const int threads = config.threads == 0 ? omp_get_max_threads() : static_cast<int>(config.threads);
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads)
  for (long qi = 0; qi < static_cast<long>(similarity.rows); ++qi) {
    const auto q = static_cast<std::size_t>(qi);
    SequenceMatch best{q, 0, 0, false};
    // The sequence ends at query q and runs back over min(len, q + 1) frames.
    const std::size_t steps = std::min(len, q + 1);
    std::size_t last_column = similarity.cols;
    if (config.self) last_column = q >= config.min_separation ? q - config.min_separation + 1 : 0;
    for (std::size_t j = 0; j < last_column; ++j) {
      for (float v : velocities) {
        double sum = 0;
        std::size_t count = 0;
        for (std::size_t k = 0; k < steps; ++k) {
          const double col = static_cast<double>(j) - static_cast<double>(v) * static_cast<double>(k);
          if (col < 0) break;
          sum += e(q - k, static_cast<std::size_t>(std::lround(col)));
          ++count;
        }
        if (count == 0) continue;
        const auto score = static_cast<float>(sum / static_cast<double>(count));
        if (!best.valid || score > best.score) best = {q, j, score, true};
      }
    }
    out[q] = best;
  }
  return out;
}

}  // namespace seqtopo::baseline
