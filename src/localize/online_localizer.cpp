#include "seqtopo/localize/online_localizer.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "seqtopo/align/online_row.hpp"

namespace seqtopo::localize {

OnlineLocalizer::OnlineLocalizer(std::size_t map_frames, const LocalizeConfig& config, std::size_t descriptors)
    : map_frames_(map_frames),
      config_(config),
      forward_(map_frames, 0.0F),
      reverse_(map_frames, 0.0F),
      previous_forward_(map_frames, 0.0F),
      previous_reverse_(map_frames, 0.0F),
      scores_(map_frames, 0.0F),
      forward_ends_(map_frames, 0),
      reverse_ends_(map_frames, 0),
      raw_(descriptors > 1 ? descriptors : 0) {
  if (map_frames == 0) throw std::invalid_argument("the map has no frame");
  if (descriptors == 0) throw std::invalid_argument("at least one descriptor");
  validate(config);
}

OnlineEstimate OnlineLocalizer::feed(std::span<const float> row) {
  return feed_descriptors(std::span<const std::span<const float>>(&row, 1));
}

OnlineEstimate OnlineLocalizer::feed_descriptors(std::span<const std::span<const float>> rows) {
  const std::size_t descriptors = std::max<std::size_t>(raw_.size(), 1);
  if (rows.size() != descriptors) {
    throw std::invalid_argument(std::to_string(rows.size()) + " similarity rows for " + std::to_string(descriptors) +
                                " descriptors");
  }
  for (const auto& row : rows) {
    if (row.size() != map_frames_) {
      throw std::invalid_argument("similarity row has " + std::to_string(row.size()) + " values, the map has " +
                                  std::to_string(map_frames_) + " frames");
    }
    for (float v : row) {
      if (!std::isfinite(v)) throw std::invalid_argument("similarity row has a non-finite value");
    }
  }
  if (raw_.empty()) {
    score_row(rows.front().data(), map_frames_, config_, scores_.data());
  } else {
    std::vector<const float*> pointers;
    for (std::size_t d = 0; d < rows.size(); ++d) {
      raw_[d].insert(raw_[d].end(), rows[d].begin(), rows[d].end());
      pointers.push_back(rows[d].data());
    }
    scratch_.resize(map_frames_);
    fused_score_row(pointers, map_frames_, config_, scores_.data(), scratch_.data(), weights_);
  }
  return advance();
}

void OnlineLocalizer::step() {
  std::swap(previous_forward_, forward_);
  std::swap(previous_reverse_, reverse_);
  const auto fill = [&](const std::vector<float>& previous, std::vector<float>& row, std::vector<std::uint8_t>& ends,
                        bool backwards) {
    align::fill_online_row(previous, scores_, row, backwards, config_.search.gap, config_.search.cap,
                           [&](std::size_t j, align::Step step, std::size_t, std::size_t) {
                             ends[j] = step == align::Step::diagonal ? 1 : 0;
                           });
  };
  fill(previous_forward_, forward_, forward_ends_, false);
  if (config_.search.reverse) fill(previous_reverse_, reverse_, reverse_ends_, true);
}

OnlineEstimate OnlineLocalizer::advance() {
  step();
  const std::size_t m = map_frames_;
  const bool reverse = config_.search.reverse;
  seen_.insert(seen_.end(), scores_.begin(), scores_.end());
  OnlineEstimate e;
  e.query = frames_seen_++;
  if (frames_seen_ == next_fit_) refit();
  bool found = false;
  // Ties keep the first cell visited (forward before reverse, smaller j) unless the row score is higher.
  auto consider = [&](float value, std::size_t j, align::Direction d) {
    const bool better = !found || value > e.score || (value == e.score && scores_[j] > scores_[e.map]);
    if (!better) return;
    found = true;
    e.score = value;
    e.map = j;
    e.direction = d;
  };
  for (std::size_t j = 0; j < m; ++j) consider(forward_[j], j, align::Direction::forward);
  if (reverse) {
    for (std::size_t j = 0; j < m; ++j) consider(reverse_[j], j, align::Direction::reverse);
  }

  // P(revisit | E): the score's E-value in the search so far (the fit's area scaled to it), as offline.
  double real = e.score >= config_.significance.threshold && e.score > 0 ? 1.0 : 0.0;
  if (fit_.valid() && e.score > 0) {
    const double area = significance::search_area(frames_seen_, m, false, 0, reverse);
    e.e_value = fit_.e_value(e.score) * area / fit_.area;
    real = significance::revisit_probability(e.e_value, *config_.significance.max_e_value);
  }
  // The posterior of where in this row the alignment ends: the guess's neighbourhood against every end. A local
  // alignment ends on a matched pair, never on a gap, so the cells reached by a gap (the same path with gaps after
  // it) are not ends of their own.
  double near = 0, all = 0;
  const std::vector<float>& best_table = e.direction == align::Direction::forward ? forward_ : reverse_;
  for (const std::vector<float>* table : {&forward_, &reverse_}) {
    const bool backwards = table == &reverse_;
    if (backwards && !reverse) break;
    const std::vector<std::uint8_t>& ends = backwards ? reverse_ends_ : forward_ends_;
    for (std::size_t j = 0; j < m; ++j) {
      if (ends[j] == 0) continue;
      const float v = (*table)[j];
      const double w = std::exp(lambda_ * (static_cast<double>(v) - e.score));
      all += w;
      if (table == &best_table && (j > e.map ? j - e.map : e.map - j) <= config_.tolerance) near += w;
    }
  }
  e.confidence = all > 0 ? real * near / all : 0.0;
  e.in_map = e.confidence >= config_.min_confidence && e.confidence > 0;
  return e;
}

void OnlineLocalizer::refit() {
  // Doubling up to kFitFrames, then every kFitFrames frames, each on the last kFitFrames rows: a refit's work (and
  // the latency of the frame that makes it) stays bounded however long the query.
  next_fit_ = next_fit_ < kFitFrames ? 2 * next_fit_ : next_fit_ + kFitFrames;
  const std::size_t rows = std::min(frames_seen_, kFitFrames), first = frames_seen_ - rows;
  const auto last_rows = [&](const std::vector<float>& all) {
    return SimilarityMatrix(
        rows, map_frames_,
        std::vector<float>(all.begin() + static_cast<std::ptrdiff_t>(first * map_frames_), all.end()));
  };
  if (frames_seen_ < kFirstFit) {
    lambda_ = significance::ungapped_lambda(seen_);
    if (!(lambda_ > 0)) lambda_ = 1.0;
    return;
  }
  if (!raw_.empty()) {
    // The descriptors' weights from the last rows (descriptor_weights); when they change, every scored row and the
    // tables are made again with them, so that the next frames extend the alignments the new weights give.
    std::vector<SimilarityMatrix> recent;
    for (const auto& raw : raw_) recent.push_back(last_rows(raw));
    std::vector<double> weights = descriptor_weights(recent, config_);
    if (weights != weights_) {
      weights_ = std::move(weights);
      std::vector<SimilarityMatrix> seen;
      for (const auto& raw : raw_) seen.emplace_back(frames_seen_, map_frames_, raw);
      const SimilarityMatrix scored = fused_score_matrix(seen, config_, weights_);
      seen_ = scored.values;
      std::fill(forward_.begin(), forward_.end(), 0.0F);
      std::fill(reverse_.begin(), reverse_.end(), 0.0F);
      for (std::size_t i = 0; i < frames_seen_; ++i) {
        std::copy_n(scored.row(i).begin(), map_frames_, scores_.begin());
        step();
      }
    }
  }
  // Karlin & Altschul's lambda of the cells bounds the gapped one of chance alignments from above (the revisit's
  // cells, counted in it, pull it somewhat below). A fit at more than twice it (the first frames' chance alignments,
  // too few and too alike to show their tail: lambda 4-90 on Nordland's first 16-32 frames, where the cells give 1.3)
  // would make every alignment significant, and is not used.
  const SimilarityMatrix recent = last_rows(seen_);
  const double ungapped = significance::ungapped_lambda(recent.values);
  const significance::ScoreStatistics fit = search_scores(recent, config_).statistics;
  if (fit.valid() && fit.lambda <= 2 * ungapped) fit_ = fit;
  lambda_ = fit_.valid() ? fit_.lambda : ungapped;
  if (!(lambda_ > 0)) lambda_ = 1.0;
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
