#include "seqtopo/mapping/map_builder.hpp"

#include <chrono>
#include <stdexcept>
#include <string>

#include "seqtopo/align/smith_waterman.hpp"

namespace seqtopo::mapping {
namespace {
double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace

MapResult build_map(const SimilarityMatrix& similarity, const MapConfig& config) {
  if (similarity.empty()) throw std::invalid_argument("empty similarity matrix");
  if (!similarity.square()) {
    throw std::invalid_argument("similarity matrix must be square, got " + std::to_string(similarity.rows) + " x " +
                                std::to_string(similarity.cols));
  }
  align::AlignConfig align_config;
  align_config.gap_a = align_config.gap_b = config.gap;
  align_config.cap = config.cap;
  align_config.threshold = config.threshold;
  align_config.self = true;
  align_config.min_separation = config.min_separation;

  MapResult result;
  auto start = std::chrono::steady_clock::now();
  const auto source = align::ScoreSource::dense(similarity.values, similarity.rows, similarity.cols);
  if (config.reverse) {
    result.alignments = align::local_alignments_both(source, align_config, config.threads);
  } else {
    result.alignments = align::local_alignments(source, align_config);
  }
  result.seconds_align = seconds_since(start);

  start = std::chrono::steady_clock::now();
  result.pruning = prune_per_column(result.alignments, config.pruning);
  std::vector<std::pair<std::size_t, std::size_t>> same_place;
  same_place.reserve(result.pruning.pairs.size());
  for (const auto& p : result.pruning.pairs) same_place.emplace_back(p.i, p.j);
  const auto labels = label_places(similarity.rows, same_place);
  result.map = build_topology(labels, result.alignments, result.pruning, config.topology);
  result.seconds_prune_label = seconds_since(start);
  return result;
}

}  // namespace seqtopo::mapping
