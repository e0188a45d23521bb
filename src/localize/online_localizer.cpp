#include "seqtopo/localize/online_localizer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "masked_scores.hpp"
#include "seqtopo/align/online_row.hpp"
#include "seqtopo/significance/low_information.hpp"

namespace seqtopo::localize {

OnlineLocalizer::OnlineLocalizer(std::size_t map_frames, const LocalizeConfig& config, std::size_t descriptors)
    : map_frames_(map_frames),
      config_(config),
      now_{.forward = Table(map_frames), .reverse = Table(map_frames), .scores = std::vector<float>(map_frames, 0.0F)},
      previous_forward_(map_frames),
      previous_reverse_(map_frames),
      raw_(descriptors > 1 ? descriptors : 0) {
  if (map_frames == 0) throw std::invalid_argument("the map has no frame");
  if (descriptors == 0) throw std::invalid_argument("at least one descriptor");
  validate(config);
}

OnlineEstimate OnlineLocalizer::feed(std::span<const float> row) {
  return feed_descriptors(std::span<const std::span<const float>>(&row, 1));
}

void OnlineLocalizer::set_low_information_map(std::span<const std::size_t> frames) {
  if (frames_seen_ > 0) throw std::invalid_argument("the map's frames of little information come before the query");
  map_masked_ = significance::frame_flags(frames, map_frames_, "low-information map frame");
}

OnlineEstimate OnlineLocalizer::feed_descriptors(std::span<const std::span<const float>> rows, bool low_information) {
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
    score_row(rows.front().data(), map_frames_, config_, now_.scores.data());
  } else {
    std::vector<const float*> pointers;
    for (std::size_t d = 0; d < rows.size(); ++d) {
      raw_[d].insert(raw_[d].end(), rows[d].begin(), rows[d].end());
      pointers.push_back(rows[d].data());
    }
    scratch_.resize(map_frames_);
    fused_score_row(pointers, map_frames_, config_, now_.scores.data(), scratch_.data(), weights_);
  }
  query_masked_.push_back(low_information);
  detail::soft_mask_row(now_.scores.data(), map_frames_, low_information, map_masked_);
  return advance();
}

void OnlineLocalizer::step() {
  std::swap(previous_forward_, now_.forward);
  std::swap(previous_reverse_, now_.reverse);
  const auto fill = [&](const Table& previous, Table& now, bool backwards) {
    align::fill_online_row(previous.values, now_.scores, now.values, backwards, config_.search.gap, config_.search.cap,
                           [&](std::size_t j, align::Step step, std::size_t diagonal_at, std::size_t left_at) {
                             now.ends[j] = step == align::Step::diagonal ? 1 : 0;
                             // The path's maximum and what its gaps cost since: the predecessor's, a new
                             // maximum resetting the cost.
                             float before = 0.0F, cost = 0.0F;
                             if (step == align::Step::diagonal && diagonal_at != align::kNoCell)
                               before = previous.peaks[diagonal_at], cost = previous.gaps[diagonal_at];
                             if (step == align::Step::up)
                               before = previous.peaks[j], cost = previous.gaps[j] + config_.search.gap;
                             if (step == align::Step::left)
                               before = now.peaks[left_at], cost = now.gaps[left_at] + config_.search.gap;
                             const bool higher = step == align::Step::none || now.values[j] >= before;
                             now.peaks[j] = step == align::Step::none ? 0.0F : std::max(before, now.values[j]);
                             now.gaps[j] = higher ? 0.0F : cost;
                           });
  };
  fill(previous_forward_, now_.forward, false);
  if (config_.search.reverse) fill(previous_reverse_, now_.reverse, true);
  if (config_.lag == 0) return;
  // The last lag + 1 frames' rows, for smoothed(); the oldest row's buffers are reused.
  Rows rows;
  if (history_.size() == config_.lag + 1) {
    rows = std::move(history_.front());
    history_.erase(history_.begin());
  }
  rows = now_;
  history_.push_back(std::move(rows));
}

OnlineEstimate OnlineLocalizer::advance() {
  step();
  seen_.insert(seen_.end(), now_.scores.begin(), now_.scores.end());
  const std::size_t frame = frames_seen_++;
  if (frames_seen_ == next_fit_) refit();
  return estimate(frame, now_, {}, {});
}

OnlineEstimate OnlineLocalizer::estimate(std::size_t frame, const Rows& rows, std::span<const float> forward_after,
                                         std::span<const float> reverse_after) const {
  const std::span<const float> scores = rows.scores;
  const std::size_t m = map_frames_;
  const bool reverse_search = config_.search.reverse;
  // G: the table value plus what the alignment gains after this frame (0 without later frames). A cell no alignment
  // reaches (F = 0) stays 0: an alignment that starts later does not pass this frame.
  const auto through = [&](std::span<const float> table, std::span<const float> after, std::size_t j) {
    return after.empty() || !(table[j] > 0) ? table[j] : table[j] + after[j];
  };
  OnlineEstimate e;
  e.query = frame;
  bool found = false;
  // Ties keep the first cell visited (forward before reverse, smaller j) unless the row score is higher.
  auto consider = [&](float value, std::size_t j, align::Direction d) {
    const bool better = !found || value > e.score || (value == e.score && scores[j] > scores[e.map]);
    if (!better) return;
    found = true;
    e.score = value;
    e.map = j;
    e.direction = d;
  };
  for (std::size_t j = 0; j < m; ++j) {
    consider(through(rows.forward.values, forward_after, j), j, align::Direction::forward);
  }
  if (reverse_search) {
    for (std::size_t j = 0; j < m; ++j) {
      consider(through(rows.reverse.values, reverse_after, j), j, align::Direction::reverse);
    }
  }

  // The guess's alignment: its path up to the path's maximum (with later frames, the best continuation's value when
  // it is higher), and how far the frame's cell has fallen below it.
  const Table& best = e.direction == align::Direction::forward ? rows.forward : rows.reverse;
  const float peak = std::max(best.peaks[e.map], e.score);
  const double fallen =
      std::min(static_cast<double>(peak) - static_cast<double>(e.score), static_cast<double>(best.gaps[e.map]));
  // P(revisit | E): the alignment's E-value in the search so far (the fit's area scaled to it), as offline.
  double real = peak >= config_.significance.threshold && peak > 0 ? 1.0 : 0.0;
  if (fit_.valid() && peak > 0) {
    const double area = significance::search_area(frames_seen_, m, false, 0, reverse_search);
    e.e_value = fit_.e_value(peak) * area / fit_.area;
    real = significance::revisit_probability(e.e_value, *config_.significance.max_e_value);
  }
  // Past the maximum, the frame is on the alignment with the odds exp(-lambda D) : 1 / m of the path going on against
  // its end there (D: what its gaps cost since; the end a priori anywhere along the map's m frames).
  if (fallen > 0) real /= 1.0 + std::exp(lambda_ * fallen) / static_cast<double>(m);
  // The posterior of where in this row the alignment passes: the guess's neighbourhood against every matched pair
  // of the row (without later frames, where an alignment ends). A local alignment ends on a matched pair, never on
  // a gap, so the cells reached by a gap (the same path with gaps after it) are not ends of their own.
  double near = 0, all = 0;
  for (const bool backwards : {false, true}) {
    if (backwards && !reverse_search) break;
    const Table& table = backwards ? rows.reverse : rows.forward;
    const std::span<const float> after = backwards ? reverse_after : forward_after;
    const bool best_table = &table == &best;
    for (std::size_t j = 0; j < m; ++j) {
      if (table.ends[j] == 0) continue;
      const double w = std::exp(lambda_ * (static_cast<double>(through(table.values, after, j)) - e.score));
      all += w;
      if (best_table && (j > e.map ? j - e.map : e.map - j) <= config_.tolerance) near += w;
    }
  }
  e.confidence = all > 0 ? real * near / all : 0.0;
  e.in_map = e.confidence >= config_.min_confidence && e.confidence > 0;
  return e;
}

OnlineEstimate OnlineLocalizer::smoothed(std::size_t frame) const {
  if (frame >= frames_seen_ || frames_seen_ - 1 - frame > config_.lag) {
    throw std::out_of_range("frame " + std::to_string(frame) + " is not among the last " +
                            std::to_string(config_.lag + 1) + " frames seen (" + std::to_string(frames_seen_) + ")");
  }
  const std::size_t m = map_frames_, later = frames_seen_ - 1 - frame;
  if (later == 0) return estimate(frame, now_, {}, {});
  const Rows& at = history_[history_.size() - 1 - later];
  // The suffix recurrence over the later frames, last first: q holds Q(r + 1, .) and becomes Q(r, .).
  const float gap = config_.search.gap;
  constexpr float kNone = -std::numeric_limits<float>::infinity();
  const auto continuation = [&](bool backwards) {
    std::vector<float> q(m, kNone), next(m, kNone);
    for (std::size_t r = history_.size() - 1; r > history_.size() - 1 - later; --r) {
      const std::vector<float>& s = history_[r].scores;
      for (std::size_t k = 0; k < m; ++k) {
        const std::size_t j = backwards ? k : m - 1 - k;  // Q(r, j) reads Q(r, j + 1) (forward) or Q(r, j - 1)
        const bool has_diagonal = backwards ? j > 0 : j + 1 < m;
        const std::size_t d = backwards ? j - 1 : j + 1;
        const float matched = s[j] + std::max(0.0F, has_diagonal ? q[d] : kNone);
        const float beside = has_diagonal ? next[d] - gap : kNone;
        next[j] = std::max({matched, q[j] - gap, beside});
      }
      std::swap(q, next);
    }
    // C(frame, j) = max(0, Q(frame + 1, j + 1)) (forward), Q(frame + 1, j - 1) (reverse).
    std::vector<float> after(m, 0.0F);
    for (std::size_t j = 0; j < m; ++j) {
      const bool has_diagonal = backwards ? j > 0 : j + 1 < m;
      if (has_diagonal) after[j] = std::max(0.0F, q[backwards ? j - 1 : j + 1]);
    }
    return after;
  };
  const std::vector<float> forward_after = continuation(false);
  const std::vector<float> reverse_after = config_.search.reverse ? continuation(true) : std::vector<float>(m, 0.0F);
  return estimate(frame, at, forward_after, reverse_after);
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
      SimilarityMatrix scored = fused_score_matrix(seen, config_, weights_);
      now_.forward = Table(map_frames_);
      now_.reverse = Table(map_frames_);
      for (std::size_t i = 0; i < frames_seen_; ++i) {
        detail::soft_mask_row(scored.row(i).data(), map_frames_, query_masked_[i], map_masked_);
        std::copy_n(scored.row(i).begin(), map_frames_, now_.scores.begin());
        step();
      }
      seen_ = std::move(scored.values);
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
