#include "seqtopo/localize/online_localizer.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace seqtopo::localize {

OnlineLocalizer::OnlineLocalizer(std::size_t map_frames, const LocalizeConfig& config)
    : map_frames_(map_frames),
      config_(config),
      forward_(map_frames, 0.0F),
      reverse_(map_frames, 0.0F),
      previous_forward_(map_frames, 0.0F),
      previous_reverse_(map_frames, 0.0F),
      scores_(map_frames, 0.0F) {
  if (map_frames == 0) throw std::invalid_argument("the map has no frame");
  validate(config);
}

OnlineEstimate OnlineLocalizer::feed(std::span<const float> row) {
  if (row.size() != map_frames_) {
    throw std::invalid_argument("similarity row has " + std::to_string(row.size()) + " values, the map has " +
                                std::to_string(map_frames_) + " frames");
  }
  for (float v : row) {
    if (!std::isfinite(v)) throw std::invalid_argument("similarity row has a non-finite value");
  }
  score_row(row.data(), map_frames_, config_, scores_.data());
  std::swap(previous_forward_, forward_);
  std::swap(previous_reverse_, reverse_);
  const float gap = config_.gap;
  auto clamp = [&](float v) { return config_.cap ? std::min(v, *config_.cap) : v; };
  const std::size_t m = map_frames_;
  // Same evaluation order and operations as the engine's fill, so values agree bit for bit.
  for (std::size_t j = 0; j < m; ++j) {
    const float diag = j > 0 ? previous_forward_[j - 1] : 0.0F;
    float v = std::max(0.0F, diag + scores_[j]);
    v = std::max(v, previous_forward_[j] - gap);
    v = std::max(v, (j > 0 ? forward_[j - 1] : 0.0F) - gap);
    forward_[j] = clamp(v);
  }
  const bool reverse = config_.reverse;
  for (std::size_t k = 0; k < m && reverse; ++k) {
    const std::size_t j = m - 1 - k;
    const float diag = j + 1 < m ? previous_reverse_[j + 1] : 0.0F;
    float v = std::max(0.0F, diag + scores_[j]);
    v = std::max(v, previous_reverse_[j] - gap);
    v = std::max(v, (j + 1 < m ? reverse_[j + 1] : 0.0F) - gap);
    reverse_[j] = clamp(v);
  }

  OnlineEstimate e;
  e.query = frames_seen_++;
  bool found = false;
  // Ties keep the first cell visited (forward before reverse, smaller j) unless the row score is higher.
  auto consider = [&](float value, std::size_t j, align::Direction d) {
    const bool better = !found || value > e.confidence || (value == e.confidence && scores_[j] > scores_[e.map]);
    if (!better) return;
    found = true;
    e.confidence = value;
    e.map = j;
    e.direction = d;
  };
  for (std::size_t j = 0; j < m; ++j) consider(forward_[j], j, align::Direction::forward);
  if (reverse) {
    for (std::size_t j = 0; j < m; ++j) consider(reverse_[j], j, align::Direction::reverse);
  }
  e.in_map = e.confidence >= config_.threshold && e.confidence > 0;
  return e;
}

std::vector<OnlineEstimate> online_estimates(const SimilarityMatrix& s, const LocalizeConfig& config) {
  if (s.empty()) throw std::invalid_argument("empty similarity matrix");
  OnlineLocalizer localizer(s.cols, config);
  std::vector<OnlineEstimate> out;
  out.reserve(s.rows);
  for (std::size_t i = 0; i < s.rows; ++i) out.push_back(localizer.feed(s.row(i)));
  return out;
}

}  // namespace seqtopo::localize
