#include "seqtopo/pipeline/baselines.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "seqtopo/localize/localize.hpp"

namespace seqtopo::pipeline {

std::vector<evaluation::ScoredPair> seqslam_loop_closures(const SimilarityMatrix& similarity,
                                                          const baseline::SeqSlamConfig& config) {
  std::vector<evaluation::ScoredPair> pairs;
  for (const auto& m : baseline::seqslam_matches(similarity, config)) {
    if (m.valid) pairs.push_back({m.query, m.match, m.score});
  }
  return pairs;
}

std::pair<float, double> best_f1_threshold(const std::vector<evaluation::PrPoint>& curve) {
  float best_threshold = 0;
  double best_f1 = -1;
  for (const auto& p : curve) {
    const double f1 = p.precision + p.recall > 0 ? 2 * p.precision * p.recall / (p.precision + p.recall) : 0.0;
    if (f1 > best_f1) {
      best_f1 = f1;
      best_threshold = p.threshold;
    }
  }
  return {best_threshold, std::max(best_f1, 0.0)};
}

std::optional<LoopClosureBaseline> seqslam_loop_closure_baseline(
    const std::vector<std::pair<std::string, const SimilarityMatrix*>>& sources, const std::vector<bool>& has_partner,
    const evaluation::SamePlace& same_place, std::size_t min_separation, unsigned threads) {
  std::optional<LoopClosureBaseline> best;
  for (const auto& [name, matrix] : sources) {
    for (const baseline::SeqSlamConfig& standard : {localization_seqslam_config(threads), short_seqslam_config()}) {
      baseline::SeqSlamConfig seqslam = standard;
      seqslam.self = true;
      seqslam.min_separation = min_separation;
      seqslam.threads = threads;
      auto pairs = seqslam_loop_closures(*matrix, seqslam);
      auto metrics = evaluation::evaluate_loop_closures(pairs, has_partner, same_place);
      if (best && metrics.auc <= best->metrics.auc) continue;
      const float threshold = best_f1_threshold(metrics.curve).first;
      std::erase_if(pairs, [&](const evaluation::ScoredPair& p) { return p.score < threshold; });
      const auto at_threshold = evaluation::evaluate_loop_closures(pairs, has_partner, same_place);
      metrics.tp = at_threshold.tp;
      metrics.fp = at_threshold.fp;
      metrics.fn = at_threshold.fn;
      metrics.precision = at_threshold.precision;
      metrics.recall = at_threshold.recall;
      metrics.f1 = at_threshold.f1;
      best = LoopClosureBaseline{
          std::move(metrics),
          fmt::format("SeqSLAM-style on {} (sequence {}, velocities {}-{}, best-F1 threshold {:.3g})", name,
                      seqslam.sequence_length, seqslam.min_velocity, seqslam.max_velocity, threshold)};
    }
  }
  return best;
}

baseline::SeqSlamConfig short_seqslam_config() {
  baseline::SeqSlamConfig c;
  c.sequence_length = 10;
  c.min_velocity = 0.8F;
  c.max_velocity = 1.25F;
  return c;
}

baseline::SeqSlamConfig localization_seqslam_config(unsigned threads) {
  baseline::SeqSlamConfig c;
  c.sequence_length = 30;
  c.min_velocity = 0.9F;
  c.max_velocity = 1.6F;
  c.velocity_steps = 8;
  c.contrast_window = 10;
  c.threads = threads;
  return c;
}

std::vector<evaluation::LocalizationPrediction> seqslam_localization(const SimilarityMatrix& query_x_map,
                                                                     const baseline::SeqSlamConfig& config) {
  std::vector<evaluation::LocalizationPrediction> out;
  for (const auto& m : baseline::seqslam_matches(query_x_map, config)) {
    evaluation::LocalizationPrediction p;
    if (m.valid && m.query + 1 >= config.sequence_length) p.map = m.match;
    p.score = m.score;
    p.candidates = {m.match};
    out.push_back(std::move(p));
  }
  return out;
}

std::vector<evaluation::LocalizationPrediction> single_frame_localization(const SimilarityMatrix& query_x_map) {
  std::vector<evaluation::LocalizationPrediction> out;
  for (const auto& f : localize::single_frame_matches(query_x_map)) {
    out.push_back({f.covered ? std::optional<std::size_t>(f.map) : std::nullopt, f.score, f.candidates});
  }
  return out;
}

}  // namespace seqtopo::pipeline
