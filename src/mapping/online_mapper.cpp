#include "seqtopo/mapping/online_mapper.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>

#include "masked_frames.hpp"
#include "median.hpp"
#include "seqtopo/align/capped_cell.hpp"
#include "seqtopo/align/online_row.hpp"
#include "seqtopo/mapping/map_builder.hpp"
#include "seqtopo/mapping/place_scale.hpp"
#include "seqtopo/significance/alignment_phase.hpp"
#include "seqtopo/similarity/contrast_enhancement.hpp"

namespace seqtopo::mapping {
namespace {

constexpr std::uint64_t kNoStart = std::numeric_limits<std::uint64_t>::max();
// The fit takes the best 1/64 of the islands died so far (at most island_sample of them, at least 48, the
// offline fit's own minimum of 30 above its first ranks with room): the islands of a few cells are many and
// fall faster than the tail, and a fit that includes them makes the E-values of the best islands too small
// (tests: with the best quarter, the islands at E <= 0.5 of noise runs average 1.05; with 1/64, 0.68).
constexpr std::size_t kMinIslandTail = 48;
constexpr std::size_t kTailFraction = 64;
// The place scale is estimated from the lags 0 .. kScaleLags of the first kScaleFrames frames (offline: 200 lags of
// every frame), again once the frames have grown by a quarter (at least 16) until then: a few milliseconds each,
// rare enough to stay out of the per-frame 99th percentile.
constexpr std::size_t kScaleLags = 200, kScaleFrames = 2000, kScaleEvery = 16;
// The scores' own phase (significance/alignment_phase.hpp) is checked on a 256 x 256 table drawn from the first
// scores, once 2,048 are in and again each time their number doubles, up to 65,536.
using significance::kPhaseCells;
using significance::kPhaseTable;
constexpr std::size_t kPhaseMinCells = 2048;

std::uint64_t cell(std::size_t i, std::size_t j) { return (static_cast<std::uint64_t>(i) << 32U) | j; }
std::size_t cell_i(std::uint64_t c) { return static_cast<std::size_t>(c >> 32U); }
std::size_t cell_j(std::uint64_t c) { return static_cast<std::size_t>(c & 0xFFFFFFFFU); }

// Row[j] is the row's largest value within `radius` columns (the first of equal ones).
bool row_peak(const std::vector<float>& row, std::size_t j, std::size_t radius) {
  const float v = row[j];
  const std::size_t lo = j >= radius ? j - radius : 0, hi = std::min(row.size() - 1, j + radius);
  for (std::size_t c = lo; c <= hi; ++c) {
    if (c < j ? row[c] >= v : (c != j && row[c] > v)) return false;
  }
  return true;
}

}  // namespace

std::string_view to_string(OnlineEventKind kind) {
  switch (kind) {
    case OnlineEventKind::loop_closure:
      return "loop_closure";
    case OnlineEventKind::revisit_begin:
      return "revisit_begin";
    case OnlineEventKind::revisit_end:
      return "revisit_end";
    case OnlineEventKind::junction:
      return "junction";
    case OnlineEventKind::place_merge:
      return "place_merge";
    case OnlineEventKind::correction:
      return "correction";
    case OnlineEventKind::revisit_candidate:
      return "revisit_candidate";
    case OnlineEventKind::session_break:
      return "session_break";
  }
  return "?";
}

void validate(const OnlineMapConfig& c) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("online mapping: " + what); };
  if (!(c.search.gap >= 0) || !std::isfinite(c.search.gap)) fail("gap must be finite and >= 0");
  if (c.search.cap && !(*c.search.cap > 0 && std::isfinite(*c.search.cap))) fail("cap must be finite and > 0");
  if (!(c.significance.threshold > 0) || !std::isfinite(c.significance.threshold))
    fail("threshold must be finite and > 0");
  if (c.search.cap && c.significance.threshold > *c.search.cap) fail("threshold must not exceed the cap");
  if (!std::isfinite(c.score.contrast_offset)) fail("contrast offset must be finite");
  if (c.phase.adapt_offset && !(c.phase.contrast_offset_step > 0 && std::isfinite(c.phase.contrast_offset_step))) {
    fail("contrast offset step must be finite and > 0");
  }
  if (c.phase.adapt_offset &&
      !(c.phase.max_contrast_offset >= c.score.contrast_offset && std::isfinite(c.phase.max_contrast_offset))) {
    fail("the largest contrast offset must be finite and at least the contrast offset");
  }
  if (c.self_similarity && !std::isfinite(*c.self_similarity)) fail("self similarity must be finite");
  if (c.phase.max_global_rate && !std::isfinite(*c.phase.max_global_rate))
    fail("the largest global rate must be finite");
  if (c.significance.max_e_value && !(*c.significance.max_e_value > 0 && std::isfinite(*c.significance.max_e_value)))
    fail("E-value must be finite and > 0");
  if (c.candidate_e_value &&
      !(std::isfinite(*c.candidate_e_value) &&
        *c.candidate_e_value > (c.significance.max_e_value ? *c.significance.max_e_value : 0.0))) {
    fail("the candidates' E-value must be finite and above the E-value");
  }
  if (c.island_sample < 64) fail("island_sample must be >= 64");
  if (!(c.x_drop > 0) || !std::isfinite(c.x_drop)) fail("x_drop must be finite and > 0");
  if (c.search.min_separation < 1) fail("min_separation must be >= 1");
  if (c.unit == align::Unit::places &&
      !(c.frames_per_place && *c.frames_per_place > 0 && std::isfinite(*c.frames_per_place)))
    fail("windows in places need frames_per_place, finite and > 0");
  if (c.distance != similarity::Distance::cosine && c.distance != similarity::Distance::sad &&
      c.distance != similarity::Distance::l1) {
    fail("distance must be cosine, sad or l1");
  }
}

OnlineMapConfig settings_in_frames(const OnlineMapConfig& config) {
  validate(config);
  OnlineMapConfig f = config;
  const double scale = config.frames_per_place.value_or(1.0);
  f.score = align::in_frames(config.score, config.unit, scale);
  f.search = align::in_frames(config.search, config.unit, scale);
  f.unit = align::Unit::frames;
  return f;
}

OnlineMapper::OnlineMapper(const OnlineMapConfig& config)
    : config_(settings_in_frames(config)),
      contrast_(config_.score.contrast_window),
      sample_(config_.island_sample),
      offset_(config.score.contrast_offset),
      threshold_(config.significance.threshold) {}

void OnlineMapper::check_row(std::span<const float> row, std::size_t expected, const char* what) const {
  if (row.size() != expected) {
    throw std::invalid_argument(std::string(what) + " of frame " + std::to_string(frames_) + " has " +
                                std::to_string(row.size()) + " values, expected " + std::to_string(expected));
  }
  for (float v : row) {
    if (!std::isfinite(v)) {
      throw std::invalid_argument(std::string(what) + " of frame " + std::to_string(frames_) +
                                  " has a non-finite value");
    }
  }
}

std::vector<OnlineEvent> OnlineMapper::add_descriptor(std::span<const float> descriptor) {
  if (frames_ == 0) {
    if (descriptor.empty()) throw std::invalid_argument("descriptor of frame 0 is empty");
    dim_ = descriptor.size();
  }
  check_row(descriptor, dim_, "descriptor");
  const std::size_t t = frames_;
  descriptors_.insert(descriptors_.end(), descriptor.begin(), descriptor.end());
  // The distances of the offline similarity (similarity/distance.hpp), to the bit: S = -D.
  if (config_.distance == similarity::Distance::cosine) norms_.push_back(similarity::squared_norm(descriptor));
  similarity_.resize(t);
  for (std::size_t j = 0; j < t; ++j) {
    const std::span<const float> other(descriptors_.data() + j * dim_, dim_);
    double d = 0;
    switch (config_.distance) {
      case similarity::Distance::cosine:
        d = similarity::cosine_distance(descriptor, other, norms_[t], norms_[j]);
        break;
      case similarity::Distance::sad:
        d = similarity::sad_distance(descriptor, other);
        break;
      default:
        d = similarity::l1_distance(descriptor, other);
        break;
    }
    similarity_[j] = -static_cast<float>(d);
  }
  enhance(similarity_);
  fill_rows();
  return step();
}

std::vector<OnlineEvent> OnlineMapper::add_similarity(std::span<const float> similarity_row) {
  if (dim_ != 0) throw std::invalid_argument("add_similarity after add_descriptor: one kind of input per mapper");
  if (channels_ > 1) throw std::invalid_argument("add_similarity after add_similarities of several rows");
  channels_ = 1;
  check_row(similarity_row, frames_, "similarity row");
  enhance(similarity_row);
  fill_rows();
  return step();
}

std::vector<OnlineEvent> OnlineMapper::add_scores(std::span<const float> scores) {
  const std::size_t t = frames_;
  const std::size_t n = t >= config_.search.min_separation ? t - config_.search.min_separation + 1 : 0;
  check_row(scores, n, "score row");
  scores_.assign(scores.begin(), scores.end());
  fill_rows();
  return step();
}

void OnlineMapper::enhance(std::span<const float> row) { enhance(std::vector<std::span<const float>>{row}); }

void OnlineMapper::enhance(const std::vector<std::span<const float>>& rows) {
  const std::size_t t = frames_;
  const std::size_t sep = config_.search.min_separation;
  const std::size_t n = t >= sep ? t - sep + 1 : 0;
  sample_lags(rows);
  contrast_.add(rows, n, scores_);
  if (contrast_.window() == 0) return;  // S aligned as it is: no offset
  for (auto& v : scores_) v -= offset_;
  if (config_.phase.adapt_offset && config_.phase.max_global_rate) {  // kept only for check_scores_phase
    for (std::size_t j = 0; j < n && phase_cells_.size() < kPhaseCells; ++j)
      phase_cells_.push_back(scores_[j] + offset_);
  }
}

void OnlineMapper::check_scores_phase() {
  if (phase_cells_.size() < std::max(kPhaseMinCells, 2 * phase_checked_at_)) return;
  phase_checked_at_ = phase_cells_.size();
  std::vector<float> cells(phase_cells_.size());
  while (offset_ + config_.phase.contrast_offset_step <= config_.phase.max_contrast_offset + 1e-6F) {
    for (std::size_t k = 0; k < cells.size(); ++k) cells[k] = phase_cells_[k] - offset_;
    const double rate = significance::resampled_global_rate(cells, kPhaseTable, config_.search.gap);
    if (rate <= *config_.phase.max_global_rate) break;
    OffsetChange change;
    change.check = "scores";
    change.global_rate = rate;
    raise_offset(std::move(change));
  }
}

void OnlineMapper::sample_lags(const std::vector<std::span<const float>>& rows) {
  const std::size_t t = frames_;
  if (!config_.self_similarity || !config_.phase.adapt_offset || t >= kScaleFrames) return;
  if (lag_samples_.size() != rows.size())
    lag_samples_.assign(rows.size(), std::vector<std::vector<float>>(kScaleLags + 1));
  for (std::size_t c = 0; c < rows.size(); ++c) {
    auto& by_lag = lag_samples_[c];
    by_lag[0].push_back(*config_.self_similarity);
    for (std::size_t k = 1; k <= std::min(kScaleLags, t); ++k) by_lag[k].push_back(rows[c][t - k]);
  }
}

void OnlineMapper::update_place_scale() {
  // The place scale of the frames so far (the mean of the similarities' that have one), as the offline map's.
  const std::size_t n = std::min(frames_ + 1, kScaleFrames);
  // Until a scale is found, every few frames (the early fit waits for it); then as the frames grow by a quarter.
  const std::size_t every = scale_found_ ? std::max(kScaleEvery, *scale_at_ / 4) : 4;
  if (scale_at_ && (frames_ >= kScaleFrames || frames_ < *scale_at_ + every)) return;
  scale_at_ = frames_;
  double sum = 0;
  std::size_t found = 0;
  const std::size_t lags = std::min(kScaleLags, n / 3);
  for (const auto& by_lag : lag_samples_) {
    if (lags < 4) break;
    // by_lag[k] holds S(t - k, t) for t < n, the pairs (i, i + k) of the first n frames.
    const PlaceScale p =
        frames_per_place_from_lags(std::vector<std::vector<float>>(by_lag.begin(), by_lag.begin() + lags + 1), n);
    if (p.found) sum += p.frames_per_place, ++found;
  }
  frames_per_place_ = found > 0 ? sum / static_cast<double>(found) : 1.0;
  scale_found_ = found > 0;
}

void OnlineMapper::check_phase(const std::vector<std::pair<double, double>>& fitted) {
  if (!config_.phase.adapt_offset || config_.score.contrast_window == 0 || lag_samples_.empty() ||
      offset_ + config_.phase.contrast_offset_step > config_.phase.max_contrast_offset + 1e-6F) {
    return;
  }
  std::vector<double> lengths;
  for (std::size_t r = statistics_.first_fitted_rank - 1; r < fitted.size(); ++r) lengths.push_back(fitted[r].second);
  if (lengths.empty()) return;
  const double frames = detail::median(std::move(lengths));
  // Within the bound counted in frames, the lengths are within it in places too (f frames a place divide the
  // length by f and lower the bound by 2 ln f only), so the scale is estimated only past it.
  if (frames <= std::max(4.0, std::log(std::max(statistics_.area, 1.0)))) return;
  update_place_scale();
  // Lengths need a scale: a smooth sequence shorter than 50 of its places, or one that drifts, has none yet.
  if (!scale_found_) return;
  const double length = frames / frames_per_place_;
  const double bound =
      std::max(4.0, std::log(std::max(statistics_.area / (frames_per_place_ * frames_per_place_), 1.0)));
  if (length <= bound) return;
  OffsetChange change;
  change.check = "islands";
  change.chance_length = length;
  change.bound = bound;
  change.frames_per_place = frames_per_place_;
  raise_offset(std::move(change));
}

// The linear phase: raise the offset for the frames that follow, and sample the islands anew (those that started
// before are scored at the old offset).
void OnlineMapper::raise_offset(OffsetChange change) {
  change.frame = frames_;
  change.from = offset_;
  change.to = offset_ + config_.phase.contrast_offset_step;
  offset_changes_.push_back(std::move(change));
  offset_ += config_.phase.contrast_offset_step;
  // Every live path is scored again as if the new offset had held from its start (one pair a frame): the paths
  // the linear phase let grow through chance fall away, a revisit keeps most of its score.
  for (auto [row, starts] : {std::pair(&forward_, &forward_start_), std::pair(&reverse_, &reverse_start_)}) {
    for (std::size_t j = 0; j < row->size(); ++j) {
      if ((*starts)[j] == kNoStart) continue;
      const auto pairs = static_cast<float>(frames_ - cell_i((*starts)[j]) + 1);
      (*row)[j] -= config_.phase.contrast_offset_step * pairs;
      if ((*row)[j] <= 0) (*row)[j] = 0, (*starts)[j] = kNoStart;
    }
  }
  for (auto& v : early_cells_) v -= config_.phase.contrast_offset_step;  // the table as at the new offset
  next_early_fit_ = 0;
  early_fitted_ = false;
  sample_.clear();
  sample_from_ = frames_ + 1;
  statistics_ = {};
  sample_changed_ = false;
  threshold_ = config_.significance.threshold;  // until the new sample is large enough for a fit
}

std::vector<OnlineEvent> OnlineMapper::add_similarities(const std::vector<std::vector<float>>& rows) {
  if (dim_ != 0) throw std::invalid_argument("add_similarities after add_descriptor: one kind of input per mapper");
  if (rows.empty()) throw std::invalid_argument("add_similarities: no similarity row");
  if (channels_ == 0) channels_ = rows.size();
  if (rows.size() != channels_) {
    throw std::invalid_argument("frame " + std::to_string(frames_) + " has " + std::to_string(rows.size()) +
                                " similarity rows, the first frame had " + std::to_string(channels_));
  }
  std::vector<std::span<const float>> spans;
  for (const auto& row : rows) {
    check_row(row, frames_, "similarity row");
    spans.emplace_back(row);
  }
  enhance(spans);
  fill_rows();
  return step();
}

std::vector<std::size_t> OnlineMapper::low_information_frames() const { return detail::flagged_frames(masked_); }

void OnlineMapper::fill_rows() {
  const std::size_t t = frames_;
  const std::size_t n = scores_.size();
  // Frames of little information: their scores at most 0 once aligned (next_frame_low_information).
  masked_.push_back(next_masked_);
  next_masked_ = false;
  if (contrast_.window() > 0) {
    for (std::size_t j = 0; j < n; ++j) {
      if (masked_[t] || masked_[j]) scores_[j] = std::min(scores_[j], 0.0F);
    }
  }
  const float gap = config_.search.gap;
  std::swap(previous_forward_, forward_);
  std::swap(previous_reverse_, reverse_);
  std::swap(previous_forward_start_, forward_start_);
  std::swap(previous_reverse_start_, reverse_start_);
  // The rows of align/online_row.hpp, and where each cell's alignment starts: the start follows the step that gives
  // the cell its value.
  const auto fill = [&](std::vector<float>& row, std::vector<std::uint64_t>& start, const std::vector<float>& previous,
                        const std::vector<std::uint64_t>& previous_start, bool reverse) {
    row.assign(n, 0.0F);
    start.assign(n, kNoStart);
    align::fill_online_row(previous, scores_, row, reverse, gap, config_.search.cap,
                           [&](std::size_t j, align::Step step, std::size_t diagonal_at, std::size_t left_at) {
                             switch (step) {
                               case align::Step::none:
                                 break;
                               case align::Step::diagonal: {
                                 const bool extends = diagonal_at != align::kNoCell && previous[diagonal_at] > 0;
                                 start[j] = extends ? previous_start[diagonal_at] : cell(t, j);
                                 break;
                               }
                               case align::Step::up:
                                 start[j] = previous_start[j];
                                 break;
                               case align::Step::left:
                                 start[j] = start[left_at];
                                 break;
                             }
                           });
  };
  fill(forward_, forward_start_, previous_forward_, previous_forward_start_, false);
  reverse_.clear();
  reverse_start_.clear();
  if (config_.search.reverse) fill(reverse_, reverse_start_, previous_reverse_, previous_reverse_start_, true);
}

float OnlineMapper::confidence(float score) const {
  // With the statistics, P(revisit | E) as the offline map's alignments (significance::revisit_probability); before
  // them, the score's share of twice the threshold.
  if (const auto e = e_value(score)) {
    return static_cast<float>(significance::revisit_probability(*e, *config_.significance.max_e_value));
  }
  const float full = config_.search.cap ? *config_.search.cap : 2 * threshold_;
  return std::min(1.0F, score / full);
}

void OnlineMapper::emit_closure(Track& track, std::size_t i, std::size_t j, float score,
                                std::vector<OnlineEvent>& events) {
  OnlineEvent e;
  e.kind = OnlineEventKind::loop_closure;
  e.frame = frames_;
  e.i = i;
  e.j = j;
  e.direction = track.direction;
  e.score = score;
  e.confidence = confidence(score);
  e.e_value = e_value(score);
  e.revisit = track.id;
  events.push_back(e);
  track.pending.push_back(closures_.size());
  closure_columns_[i].emplace_back(j, track.direction);
  closures_.push_back({i, j, track.id, track.direction, e.confidence, false});
}

OnlineEvent OnlineMapper::closure_event(OnlineEventKind kind, const Closure& c) const {
  OnlineEvent e;
  e.kind = kind;
  e.frame = frames_;
  e.i = c.i;
  e.j = c.j;
  e.direction = c.direction;
  e.revisit = c.revisit;
  return e;
}

void OnlineMapper::settle(Track& track, std::size_t up_to, std::vector<OnlineEvent>& events) {
  std::vector<std::size_t> keep;
  for (std::size_t index : track.pending) {
    const Closure& c = closures_[index];
    if (c.i > up_to) {
      keep.push_back(index);
      continue;
    }
    const std::size_t a = places_.find(c.i), b = places_.find(c.j);
    if (a == b) continue;
    if (places_.set_size(a) >= 2 && places_.set_size(b) >= 2) {
      OnlineEvent e = closure_event(OnlineEventKind::place_merge, c);
      e.first = std::min(a, b);
      e.last = std::max(a, b);
      events.push_back(e);
    }
    places_.unite(a, b);  // a place is named by its first frame
  }
  track.pending = std::move(keep);
}

void OnlineMapper::add_junction(const Track& track, std::size_t i, std::size_t j, bool joining,
                                std::vector<OnlineEvent>& events) {
  const std::size_t place = places_.find(j);
  for (std::size_t known : junction_places_) {
    if (places_.find(known) == place || (known > j ? known - j : j - known) <= config_.reach) return;
  }
  junction_places_.push_back(j);
  OnlineEvent e;
  e.kind = OnlineEventKind::junction;
  e.frame = frames_;
  e.i = i;
  e.j = j;
  e.direction = track.direction;
  e.revisit = track.id;
  e.joining = joining;
  e.score = track.best;
  events.push_back(e);
}

void OnlineMapper::end_track(Track& track, bool at_finish, std::vector<OnlineEvent>& events) {
  ended_starts_[cell(track.first_i, track.first_j)] = track.last_i;
  const bool too_short = track.best_i - track.first_i + 1 < config_.min_revisit_frames;
  const std::size_t keep_to = too_short ? track.first_i : track.best_i;
  OnlineEvent correction;
  correction.kind = OnlineEventKind::correction;
  correction.frame = frames_;
  correction.direction = track.direction;
  correction.revisit = track.id;
  correction.reason = too_short ? "the revisit was shorter than min_revisit_frames"
                                : "frames after the revisit's end (the last frame at its best score)";
  std::vector<std::size_t> settled_now;
  for (std::size_t index : track.pending) {
    Closure& c = closures_[index];
    if (too_short || c.i > keep_to) {
      c.withdrawn = true;
      correction.withdrawn.emplace_back(c.i, c.j);
    }
  }
  std::erase_if(track.pending, [&](std::size_t index) { return closures_[index].withdrawn; });
  if (!too_short) settle(track, track.best_i, events);
  if (!correction.withdrawn.empty()) {
    correction.i = correction.withdrawn.front().first;
    correction.j = correction.withdrawn.front().second;
    events.push_back(std::move(correction));
  }
  if (too_short) return;
  revisit_best_[track.id] = track.best;
  OnlineEvent e;
  e.kind = OnlineEventKind::revisit_end;
  e.frame = frames_;
  e.i = track.best_i;
  e.j = track.best_j;
  e.direction = track.direction;
  e.revisit = track.id;
  e.score = track.best;
  e.confidence = confidence(track.best);
  e.e_value = e_value(track.best);
  e.first = track.first_i;
  e.last = track.best_i;
  e.frames = track.best_i - track.first_i + 1;
  events.push_back(e);
  if (at_finish) return;
  // Leaving the old path in its middle: it continues beyond the old frame the revisit ended on.
  const bool forward = track.direction == align::Direction::forward;
  const bool middle = forward ? track.best_j + config_.reach < track.first_i : track.best_j > config_.reach;
  if (middle) add_junction(track, track.best_i, track.best_j, false, events);
}

void OnlineMapper::update_tracks(align::Direction direction, std::vector<OnlineEvent>& events) {
  const bool forward = direction == align::Direction::forward;
  const std::vector<float>& row = forward ? forward_ : reverse_;
  const std::vector<std::uint64_t>& starts = forward ? forward_start_ : reverse_start_;
  const std::size_t t = frames_;
  const std::size_t n = row.size();
  const std::size_t reach = config_.reach;
  // Continue the live tracks: the best cell near the predicted column (first maximum). A track that falls below
  // the threshold (or x_drop below its best) is dormant, without loop closures, while the path it followed lives
  // on in the table (a cell still carries its start cell): a stretch of poor frames inside one revisit.
  std::vector<std::size_t> ended;
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    Track& track = tracks_[k];
    if (track.direction != direction) continue;
    const std::uint64_t own_start = cell(track.first_i, track.first_j);
    if (track.dormant) {
      long best = -1;
      for (std::size_t j = 0; j < n; ++j) {
        if (starts[j] == own_start && (best < 0 || row[j] > row[static_cast<std::size_t>(best)])) {
          best = static_cast<long>(j);
        }
      }
      if (best < 0) {
        ended.push_back(k);
        continue;
      }
      const float value = row[static_cast<std::size_t>(best)];
      if (value < threshold_ || value < track.best - config_.x_drop || value <= track.sleep_value) continue;
      // Resumed: the frames it slept through get loop closures along the line from its last cell to this one.
      const std::size_t span = t - track.last_i;
      for (std::size_t i = track.last_i + 1; i < t; ++i) {
        const double f = static_cast<double>(i - track.last_i) / static_cast<double>(span);
        const double jj = static_cast<double>(track.last_j) + f * (static_cast<double>(best) - track.last_j);
        emit_closure(track, i, static_cast<std::size_t>(std::lround(jj)), value, events);
      }
      track.dormant = false;
      track.falling = 0;
      track.last_value = value;
      track.last_i = t;
      track.last_j = static_cast<std::size_t>(best);
      emit_closure(track, t, track.last_j, value, events);
      if (value >= track.best) {
        track.best = value;
        track.best_i = t;
        track.best_j = track.last_j;
      }
      settle(track, t, events);
      continue;
    }
    const long predicted = static_cast<long>(track.last_j) + (forward ? 1 : -1);
    const long lo = std::max(0L, predicted - static_cast<long>(reach));
    const long hi = std::min(static_cast<long>(n) - 1, predicted + static_cast<long>(reach));
    long best = -1;
    for (long j = lo; j <= hi; ++j) {
      const auto at = static_cast<std::size_t>(j);
      // Capped cells tie: among them the frame's own evidence, its score with column j, decides (the first
      // maximum would keep the path on one side of a smooth revisit's band of diagonals).
      if (best < 0 || row[at] > row[static_cast<std::size_t>(best)] ||
          (row[at] == row[static_cast<std::size_t>(best)] && scores_[at] > scores_[static_cast<std::size_t>(best)])) {
        best = j;
      }
    }
    const float value = best >= 0 ? row[static_cast<std::size_t>(best)] : 0.0F;
    // A score falling frame after frame is a revisit that has ended (or a poor stretch): asleep until its path
    // climbs above where it fell asleep.
    // So is a path that no longer matches: the cell not reached by a diagonal step onto a positive score (a capped
    // path can otherwise wander through gaps from one revisit's cells to another's).
    bool matching = false;
    if (best >= 0) {
      const auto jb = static_cast<std::size_t>(best);
      const std::vector<float>& previous = forward ? previous_forward_ : previous_reverse_;
      const std::size_t from = forward ? jb - 1 : jb + 1;  // wraps for jb = 0 forward: out of range, no diagonal
      const float diag = from < previous.size() ? previous[from] : 0.0F;
      // A frame of little information scores 0 at most: a path through a tunnel seen twice neither gains nor
      // loses, and still matches.
      const bool masked = masked_[t] || masked_[jb];
      matching = (scores_[jb] > 0 || (masked && scores_[jb] == 0)) &&
                 align::capped(diag + scores_[jb], config_.search.cap) == value;
    }
    track.falling = best >= 0 && (value < track.last_value || !matching) ? track.falling + 1 : 0;
    if (best < 0 || value < threshold_ || value < track.best - config_.x_drop ||
        (config_.patience > 0 && track.falling >= config_.patience)) {
      track.dormant = true;
      track.sleep_value = value;
      continue;
    }
    track.last_value = value;
    track.last_i = t;
    track.last_j = static_cast<std::size_t>(best);
    emit_closure(track, t, track.last_j, value, events);
    if (value >= track.best) {
      track.best = value;
      track.best_i = t;
      track.best_j = track.last_j;
      if (t - track.first_i + 1 >= config_.min_revisit_frames) settle(track, t, events);
    }
  }
  // Two tracks on the same cells are one revisit: the later one ends.
  for (std::size_t a = 0; a < tracks_.size(); ++a) {
    for (std::size_t b = a + 1; b < tracks_.size(); ++b) {
      const Track &x = tracks_[a], &y = tracks_[b];
      if (x.direction != direction || y.direction != direction || x.last_i != t || y.last_i != t) continue;
      if (x.dormant || y.dormant) continue;
      const std::size_t d = x.last_j > y.last_j ? x.last_j - y.last_j : y.last_j - x.last_j;
      if (d <= reach && std::find(ended.begin(), ended.end(), b) == ended.end()) ended.push_back(b);
    }
  }
  std::sort(ended.begin(), ended.end());
  for (auto it = ended.rbegin(); it != ended.rend(); ++it) {
    end_track(tracks_[*it], false, events);
    tracks_.erase(tracks_.begin() + static_cast<std::ptrdiff_t>(*it));
  }
  // New tracks: cells at threshold or above, maximal within min_separation columns, and that far from every live
  // track of this direction (the diagonals beside a revisit score almost as well: they are the same revisit).
  const std::size_t radius = config_.search.min_separation;
  for (std::size_t j = 0; j < n; ++j) {
    const float v = row[j];
    if (v < threshold_ || starts[j] == kNoStart) continue;
    if (!row_peak(row, j, radius) || near_a_track(direction, starts[j], j)) continue;
    Track track;
    track.id = next_track_++;
    track.direction = direction;
    track.first_i = cell_i(starts[j]);
    track.first_j = cell_j(starts[j]);
    track.last_i = t;
    track.last_j = j;
    track.best = v;
    track.best_i = t;
    track.best_j = j;
    track.last_value = v;
    OnlineEvent begin;
    begin.kind = OnlineEventKind::revisit_begin;
    begin.frame = t;
    begin.i = track.first_i;
    begin.j = track.first_j;
    begin.direction = direction;
    begin.score = v;
    begin.confidence = confidence(v);
    begin.e_value = e_value(v);
    begin.revisit = track.id;
    begin.first = track.first_i;
    begin.last = t;
    begin.frames = t - track.first_i + 1;
    if (auto it = near_candidate(starts[j], direction); it != candidates_.end()) {
      begin.candidate = it->second;  // confirmed
      candidates_.erase(it);
    }
    events.push_back(begin);
    // Joining the old path in its middle (forward: frames before the old one lead into it; reverse: not a U-turn).
    const bool middle =
        forward ? track.first_j > reach : track.first_i - track.first_j > config_.search.min_separation + 2 * reach;
    if (middle) add_junction(track, track.first_i, track.first_j, true, events);
    // The frames between the start and now, along the line from the start cell to this one; an alignment that
    // an ended track followed already (the same start cell) is filled only after that track's last frame.
    const std::size_t span = t - track.first_i;
    std::size_t fill_from = track.first_i;
    if (auto it = ended_starts_.find(cell(track.first_i, track.first_j)); it != ended_starts_.end()) {
      fill_from = std::max(fill_from, it->second + 1);
    }
    for (std::size_t i = fill_from; i < t; ++i) {
      const double f = span == 0 ? 0.0 : static_cast<double>(i - track.first_i) / static_cast<double>(span);
      const double jj = static_cast<double>(track.first_j) + f * (static_cast<double>(j) - track.first_j);
      emit_closure(track, i, static_cast<std::size_t>(std::lround(jj)), v, events);
    }
    emit_closure(track, t, j, v, events);
    if (begin.frames >= config_.min_revisit_frames) settle(track, t, events);
    tracks_.push_back(std::move(track));
  }
}

bool OnlineMapper::near_a_track(align::Direction direction, std::uint64_t start, std::size_t j) const {
  return std::any_of(tracks_.begin(), tracks_.end(), [&](const Track& track) {
    const std::size_t d = track.last_j > j ? track.last_j - j : j - track.last_j;
    // the path of a (dormant) track, or a column beside one
    return track.direction == direction &&
           (cell(track.first_i, track.first_j) == start || d <= config_.search.min_separation);
  });
}

bool OnlineMapper::near_cells(std::uint64_t a, std::uint64_t b) const {
  const auto apart = [](std::size_t x, std::size_t y) { return x > y ? x - y : y - x; };
  return apart(cell_i(a), cell_i(b)) <= config_.search.min_separation &&
         apart(cell_j(a), cell_j(b)) <= config_.search.min_separation;
}

OnlineMapper::Candidates::iterator OnlineMapper::near_candidate(std::uint64_t start, align::Direction direction) {
  for (auto it = candidates_.begin(); it != candidates_.end(); ++it) {
    if (it->first.second == direction && near_cells(it->first.first, start)) return it;
  }
  return candidates_.end();
}

void OnlineMapper::find_candidates(align::Direction direction, std::vector<OnlineEvent>& events) {
  if (!config_.candidate_e_value || !statistics_.valid()) return;
  const double at = statistics_.score_at(*config_.candidate_e_value);
  const bool forward = direction == align::Direction::forward;
  const std::vector<float>& row = forward ? forward_ : reverse_;
  const std::vector<std::uint64_t>& starts = forward ? forward_start_ : reverse_start_;
  const std::size_t radius = config_.search.min_separation;
  for (std::size_t j = 0; j < row.size(); ++j) {
    const float v = row[j];
    if (v < at || v >= threshold_ || starts[j] == kNoStart || !row_peak(row, j, radius)) continue;
    if (near_candidate(starts[j], direction) != candidates_.end() || ended_starts_.contains(starts[j])) continue;
    if (near_a_track(direction, starts[j], j)) continue;
    const std::size_t id = next_candidate_++;
    candidates_.emplace(std::pair(starts[j], direction), id);
    OnlineEvent e;
    e.kind = OnlineEventKind::revisit_candidate;
    e.frame = frames_;
    e.i = frames_;
    e.j = j;
    e.first = cell_i(starts[j]);
    e.last = cell_j(starts[j]);
    e.direction = direction;
    e.score = v;
    e.confidence = confidence(v);
    e.e_value = e_value(v);
    e.candidate = id;
    events.push_back(e);
  }
}

void OnlineMapper::drop_candidates(align::Direction direction, const significance::IslandRow* live,
                                   std::vector<OnlineEvent>& events) {
  const bool at_finish = live == nullptr;
  for (auto it = candidates_.begin(); it != candidates_.end();) {
    if (it->first.second != direction || (live && live->find(it->first.first) != nullptr)) {
      ++it;
      continue;
    }
    // A path re-rooted through a gap carries a start cell next to the old one: the candidate follows it (the
    // nearby start whose island scores best, the smallest start cell of equal ones).
    if (live) {
      std::optional<std::pair<float, std::uint64_t>> heir;
      for (const auto& [start, island] : live->islands) {
        if (!near_cells(start, it->first.first) || candidates_.contains({start, direction})) continue;
        const std::pair<float, std::uint64_t> key{island.best, ~start};
        if (!heir || key > *heir) heir = key;
      }
      if (heir) {
        const std::size_t id = it->second;
        it = candidates_.erase(it);
        candidates_.emplace(std::pair(~heir->second, direction), id);
        continue;  // a key before or after `it`: visited again at most once, alive then
      }
    }
    OnlineEvent e;
    e.kind = OnlineEventKind::correction;
    e.frame = frames_;
    e.direction = direction;
    e.candidate = it->second;
    e.reason = at_finish
                   ? "the run ended before revisit candidate " + std::to_string(it->second) + " reached the threshold"
                   : "revisit candidate " + std::to_string(it->second) + " did not reach the threshold";
    events.push_back(std::move(e));
    it = candidates_.erase(it);
  }
}

std::vector<double> OnlineMapper::island_scores() const {
  std::vector<double> out;
  for (const auto& island : sample_.best()) out.push_back(island.first);
  return out;
}

bool OnlineMapper::beside_a_revisit(const significance::Island& island, align::Direction direction) const {
  const auto it = closure_columns_.find(island.i);
  if (it == closure_columns_.end()) return false;
  for (const auto& [j, d] : it->second) {
    if (d == direction && (j > island.j ? j - island.j : island.j - j) <= config_.search.min_separation) return true;
  }
  return false;
}

void OnlineMapper::update_islands(align::Direction direction, significance::OnlineIslands& islands) {
  const bool forward = direction == align::Direction::forward;
  islands.advance(forward ? forward_ : reverse_, forward ? forward_start_ : reverse_start_, frames_,
                  [&](std::uint64_t start, const significance::Island& island) {
                    if (cell_i(start) < sample_from_ || beside_a_revisit(island, direction)) return;
                    const double length = static_cast<double>(island.i - cell_i(start) + 1);
                    if (sample_.offer({island.best, length})) sample_changed_ = true;
                  });
}

void OnlineMapper::fit_early(double area) {
  const std::size_t n = frames_ + 1, sep = config_.search.min_separation;
  // Only a sequence of 50 places or more has a scale (place_scale.hpp); a shorter one, or a smooth one whose
  // chance alignments are few and long, gives too few independent ones for a fit.
  if (n <= config_.early_fit_frames && n >= next_early_fit_) {
    if (!lag_samples_.empty()) update_place_scale();
    if (scale_found_) {
      next_early_fit_ = n + std::max<std::size_t>(4, n / 8);
      // The rows so far as the lower triangle of a square table: the self search reads only i - j >= sep.
      std::vector<float> table(n * n, 0.0F);
      std::size_t at = 0;
      for (std::size_t i = sep; i < n; ++i) {
        std::copy_n(early_cells_.begin() + static_cast<std::ptrdiff_t>(at), i - sep + 1, table.begin() + i * n);
        at += i - sep + 1;
      }
      MapConfig c;
      c.search = config_.search;
      c.search.min_separation = sep;
      c.threads = 1;
      // Trusted only where the offline map would trust them, in the logarithmic phase by both its checks (at its
      // own bound on the global rate, whatever the online setting): in the linear phase the mapper's own checks
      // raise the offset first, or the islands wait for more frames.
      const TableFit fit = fit_table_statistics(align::ScoreSource::dense(table, n, n), c, frames_per_place_);
      early_fitted_ = fit.logarithmic;
      statistics_ = early_fitted_ ? fit.statistics : significance::ScoreStatistics{};
    }
  }
  if (early_fitted_) statistics_.area = area;  // the fit of the frames so far, extrapolated past the last one
}

void OnlineMapper::update_threshold() {
  const std::size_t tail = std::min(sample_.size(), sample_.offered() / kTailFraction);
  const double area =
      significance::search_area(frames_ + 1, frames_ + 1, true, config_.search.min_separation, config_.search.reverse);
  if (config_.significance.max_e_value && tail < kMinIslandTail && config_.early_fit_frames > 0) fit_early(area);
  if (!config_.significance.max_e_value || (tail < kMinIslandTail && !early_fitted_)) {
    threshold_ = config_.significance.threshold;
    return;
  }
  if (tail >= kMinIslandTail && (sample_changed_ || !statistics_.valid() || early_fitted_)) {
    early_fitted_ = false;
    // The best `tail` islands, best first: their scores for the fit, their lengths for the phase check.
    std::vector<std::pair<double, double>> sample = sample_.best();
    sample.resize(tail);
    std::vector<double> scores(tail);
    for (std::size_t r = 0; r < tail; ++r) scores[r] = sample[r].first;
    statistics_ = significance::fit_declumped_scores(scores, area);
    sample_changed_ = false;
    if (statistics_.valid()) check_phase(sample);
  }
  statistics_.area = area;
  if (!statistics_.valid()) {
    threshold_ = config_.significance.threshold;
    return;
  }
  const double at = statistics_.score_at(*config_.significance.max_e_value);
  const float cap = config_.search.cap ? *config_.search.cap : std::numeric_limits<float>::max();
  threshold_ = static_cast<float>(std::clamp(at, 1e-3, static_cast<double>(cap)));
}

std::optional<double> OnlineMapper::e_value(float score) const {
  if (!config_.significance.max_e_value || !statistics_.valid()) return std::nullopt;
  return statistics_.e_value(score);
}

std::vector<OnlineEvent> OnlineMapper::step() {
  if (config_.significance.max_e_value && frames_ < config_.early_fit_frames) {
    early_cells_.insert(early_cells_.end(), scores_.begin(), scores_.end());
  } else {
    std::vector<float>().swap(early_cells_);
  }
  places_.add();
  std::vector<OnlineEvent> events;
  update_tracks(align::Direction::forward, events);
  if (config_.search.reverse) update_tracks(align::Direction::reverse, events);
  // Candidates at this frame's statistics, as its tracks.
  find_candidates(align::Direction::forward, events);
  if (config_.search.reverse) find_candidates(align::Direction::reverse, events);
  // The islands that died in this row, after its loop closures (so that a revisit's shadows stay out of the
  // sample), and the threshold of the next frame; without an E-value neither is used. A candidate whose path
  // died with them is withdrawn.
  if (config_.significance.max_e_value) {
    update_islands(align::Direction::forward, forward_islands_);
    drop_candidates(align::Direction::forward, &forward_islands_.live(), events);
    if (config_.search.reverse) {
      update_islands(align::Direction::reverse, reverse_islands_);
      drop_candidates(align::Direction::reverse, &reverse_islands_.live(), events);
    }
  }
  update_threshold();
  if (config_.phase.adapt_offset && config_.phase.max_global_rate && config_.score.contrast_window > 0)
    check_scores_phase();
  ++frames_;
  return events;
}

std::vector<OnlineEvent> OnlineMapper::finish() {
  std::vector<OnlineEvent> events;
  for (Track& track : tracks_) end_track(track, true, events);
  tracks_.clear();
  drop_candidates(align::Direction::forward, nullptr, events);
  drop_candidates(align::Direction::reverse, nullptr, events);
  review_closures(events);
  // Emitted after the last frame.
  for (auto& e : events) e.frame = frames_ == 0 ? 0 : frames_ - 1;
  return events;
}

void OnlineMapper::review_closures(std::vector<OnlineEvent>& events) {
  // Every revisit judged again under the last statistics, as the offline map judges its alignments under the
  // whole sequence's: one confirmed early, when the fit had few frames, may be insignificant now (withdrawn); the
  // others' loop closures take the confidence of their revisit's best score now.
  if (!config_.significance.max_e_value || !statistics_.valid()) return;
  std::map<std::size_t, OnlineEvent> corrections;  // by revisit
  for (Closure& c : closures_) {
    const auto best = revisit_best_.find(c.revisit);
    if (c.withdrawn || best == revisit_best_.end()) continue;
    const double e = statistics_.e_value(best->second);
    if (e <= *config_.significance.max_e_value) {
      c.confidence = confidence(best->second);
      continue;
    }
    c.withdrawn = true;
    auto [it, added] = corrections.try_emplace(c.revisit);
    OnlineEvent& correction = it->second;
    if (added) {
      correction = closure_event(OnlineEventKind::correction, c);
      correction.e_value = e;
      correction.score = best->second;
      correction.reason = fmt::format("insignificant under the statistics of the whole run (E {:.3g} > {:.3g})", e,
                                      *config_.significance.max_e_value);
    }
    correction.withdrawn.emplace_back(c.i, c.j);
  }
  if (corrections.empty()) return;
  for (auto& [revisit, correction] : corrections) events.push_back(std::move(correction));
  // The places again from the loop closures that stand (a place is named by its first frame).
  DisjointSets<std::size_t> places(frames_);
  for (const Closure& c : closures_) {
    if (!c.withdrawn) places.unite(places.find(c.i), places.find(c.j));
  }
  places_ = std::move(places);
}

std::vector<OnlineLoopClosure> OnlineMapper::loop_closures() const {
  std::vector<OnlineLoopClosure> out;
  for (const auto& c : closures_) {
    if (!c.withdrawn) out.push_back({c.i, c.j, c.direction, c.confidence, c.revisit});
  }
  std::sort(out.begin(), out.end(),
            [](const auto& a, const auto& b) { return std::pair(a.i, a.j) < std::pair(b.i, b.j); });
  return out;
}

std::vector<std::size_t> OnlineMapper::places() {
  std::vector<std::size_t> out(frames_);
  for (std::size_t f = 0; f < frames_; ++f) out[f] = places_.find(f);
  return out;
}

}  // namespace seqtopo::mapping
