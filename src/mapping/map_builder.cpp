#include "seqtopo/mapping/map_builder.hpp"

#include <chrono>
#include <stdexcept>
#include <string>

#include "seqtopo/align/fast_alignment.hpp"
#include "seqtopo/align/smith_waterman.hpp"
#include "seqtopo/similarity/contrast_enhancement.hpp"

namespace seqtopo::mapping {
namespace {
double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace

SimilarityMatrix alignment_scores(const std::vector<SimilarityMatrix>& similarities, const MapConfig& config) {
  if (similarities.empty() || similarities.front().empty()) throw std::invalid_argument("empty similarity matrix");
  const std::size_t n = similarities.front().rows;
  for (const auto& s : similarities) {
    if (!s.square() || s.rows != n) {
      throw std::invalid_argument("similarity matrix must be square and " + std::to_string(n) + " x " +
                                  std::to_string(n) + ", got " + std::to_string(s.rows) + " x " +
                                  std::to_string(s.cols));
    }
  }
  if (similarities.size() == 1) {
    return config.contrast_window == 0 ? similarities.front()
                                       : similarity::enhance_contrast_symmetric(
                                             similarities.front(), config.contrast_window, config.contrast_offset);
  }
  SimilarityMatrix sum(n, n, 0.0F);
  for (const auto& s : similarities) {
    const SimilarityMatrix e =
        config.contrast_window == 0 ? s : similarity::enhance_contrast_symmetric(s, config.contrast_window, 0.0F);
    for (std::size_t k = 0; k < sum.values.size(); ++k) sum.values[k] += e.values[k];
  }
  const float offset = config.contrast_window == 0 ? 0.0F : config.contrast_offset;
  const auto count = static_cast<float>(similarities.size());
  for (auto& v : sum.values) v = v / count - offset;
  return sum;
}

align::AlignConfig align_config(const MapConfig& config) {
  align::AlignConfig c;
  c.gap_a = c.gap_b = config.gap;
  c.cap = config.cap;
  c.threshold = config.threshold;
  c.self = true;
  c.min_separation = config.min_separation;
  return c;
}

MapResult build_map(const SimilarityMatrix& similarity, const MapConfig& config, std::span<const Pose2> odometry) {
  return build_map(std::vector<SimilarityMatrix>{similarity}, config, odometry);
}

MapResult build_map(const std::vector<SimilarityMatrix>& similarities, const MapConfig& config,
                    std::span<const Pose2> odometry) {
  const auto start = std::chrono::steady_clock::now();
  SimilarityMatrix scores = alignment_scores(similarities, config);
  const double seconds_scores = seconds_since(start);
  MapResult result =
      build_map_from_scores(align::ScoreSource::dense(scores.values, scores.rows, scores.cols), config, odometry);
  result.scores = std::move(scores);
  result.seconds_align += seconds_scores;
  return result;
}

MapResult build_map_from_scores(const align::ScoreSource& scores, const MapConfig& config,
                                std::span<const Pose2> odometry) {
  const std::size_t n = scores.rows();
  if (n == 0 || scores.cols() != n) {
    throw std::invalid_argument("score source must be square and non-empty, got " + std::to_string(n) + " x " +
                                std::to_string(scores.cols()));
  }
  if (!odometry.empty() && odometry.size() != n) {
    throw std::invalid_argument("odometry has " + std::to_string(odometry.size()) + " poses, the sequence " +
                                std::to_string(n) + " images");
  }
  MapResult result;
  auto start = std::chrono::steady_clock::now();
  const align::AlignConfig engine_config = align_config(config);
  if (config.engine == MapConfig::Engine::fast) {
    const align::FastOptions options{.threads = config.threads};
    result.alignments = config.reverse ? align::fast_local_alignments_both(scores, engine_config, options)
                                       : align::fast_local_alignments(scores, engine_config, options);
  } else if (config.reverse) {
    result.alignments = align::local_alignments_both(scores, engine_config, config.threads);
  } else {
    result.alignments = align::local_alignments(scores, engine_config);
  }
  if (!odometry.empty() && config.odometry_gate) {
    const std::vector<bool> keep = consistent_with_odometry(result.alignments, odometry, *config.odometry_gate);
    std::vector<align::LocalAlignment> kept;
    for (std::size_t k = 0; k < keep.size(); ++k)
      (keep[k] ? kept : result.rejected).push_back(std::move(result.alignments[k]));
    result.alignments = std::move(kept);
  }
  result.seconds_align = seconds_since(start);

  start = std::chrono::steady_clock::now();
  result.pruning = prune_per_column(result.alignments, config.pruning);
  std::vector<std::pair<std::size_t, std::size_t>> same_place;
  same_place.reserve(result.pruning.pairs.size());
  for (const auto& p : result.pruning.pairs) same_place.emplace_back(p.i, p.j);
  const auto labels = label_places(n, same_place);
  result.map = build_topology(labels, result.alignments, result.pruning, config.topology);
  result.seconds_prune_label = seconds_since(start);
  return result;
}

}  // namespace seqtopo::mapping
