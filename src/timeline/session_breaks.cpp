#include "seqtopo/timeline/session_breaks.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace seqtopo::timeline {

namespace {

// The frames of [begin, end) ranks are measured against: all of them, or `count` spread evenly.
std::vector<std::size_t> spread(std::size_t begin, std::size_t end, std::size_t count) {
  std::vector<std::size_t> out;
  const std::size_t n = end - begin;
  const std::size_t m = std::min(n, count);
  out.reserve(m);
  for (std::size_t k = 0; k < m; ++k) out.push_back(begin + k * n / m);
  return out;
}

// Throws std::invalid_argument unless frame k's time is finite and not before the previous frame's.
void check_time(std::size_t k, double time, std::optional<double> previous) {
  if (!std::isfinite(time)) throw std::invalid_argument("frame time " + std::to_string(k) + " is not finite");
  if (previous && time < *previous) throw std::invalid_argument("frame times decrease at frame " + std::to_string(k));
}

// The gap rule: an interval long against the recording's median one, and long in itself.
bool is_gap(double interval, double median, const SessionBreakConfig& config) {
  return median > 0 && interval >= config.gap_factor * median && interval >= config.min_gap;
}

// The neighbour rule: `rank` reaches config.neighbour_quantile of the recording's own steps' ranks (none: it does
// not) and config.min_neighbour_rank.
bool ranks_as_neighbours(double rank, std::vector<double> steps, const SessionBreakConfig& config) {
  if (steps.empty()) return false;
  std::sort(steps.begin(), steps.end());
  const auto at = static_cast<std::size_t>(config.neighbour_quantile * static_cast<double>(steps.size() - 1));
  return rank >= std::max(steps[at], config.min_neighbour_rank);
}

}  // namespace

std::vector<TimeGap> time_gaps(std::span<const double> times, const SessionBreakConfig& config) {
  for (std::size_t k = 0; k < times.size(); ++k) {
    check_time(k, times[k], k > 0 ? std::optional<double>(times[k - 1]) : std::nullopt);
  }
  if (times.size() < 3) return {};
  std::vector<double> intervals;
  intervals.reserve(times.size() - 1);
  for (std::size_t k = 1; k < times.size(); ++k) intervals.push_back(times[k] - times[k - 1]);
  std::vector<double> sorted = intervals;
  const auto middle = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), middle, sorted.end());
  const double median = *middle;
  std::vector<TimeGap> gaps;
  for (std::size_t k = 0; k < intervals.size(); ++k) {
    if (is_gap(intervals[k], median, config)) gaps.push_back({k + 1, intervals[k], median});
  }
  return gaps;
}

double neighbour_rank(const Similarity& similarity, std::size_t a, std::size_t b, std::size_t begin, std::size_t end,
                      const SessionBreakConfig& config) {
  const double ab = similarity(a, b);
  std::size_t others = 0, below_a = 0, below_b = 0;
  for (std::size_t j : spread(begin, end, config.rank_columns)) {
    if (j == a || j == b) continue;
    ++others;
    below_a += similarity(a, j) < ab ? 1 : 0;
    below_b += similarity(b, j) < ab ? 1 : 0;
  }
  if (others == 0) return 1.0;  // no other frame to be less alike to
  return static_cast<double>(std::min(below_a, below_b)) / static_cast<double>(others);
}

bool looks_like_neighbours(const Similarity& similarity, std::size_t a, std::size_t b, std::size_t begin,
                           std::size_t end, const std::function<bool(std::size_t)>& skip,
                           const SessionBreakConfig& config) {
  const auto skipped = [&skip](std::size_t f) { return skip && skip(f); };
  if (skipped(a) || skipped(b)) return false;  // a frame of no information says nothing either way
  if (end - begin < 2) return false;
  std::vector<double> ranks;
  for (std::size_t k : spread(begin + 1, end, config.rank_steps)) {
    if (k - 1 == a || skipped(k - 1) || skipped(k)) continue;
    ranks.push_back(neighbour_rank(similarity, k - 1, k, begin, end, config));
  }
  if (ranks.empty()) return false;  // nothing to compare with: the times decide
  return ranks_as_neighbours(neighbour_rank(similarity, a, b, begin, end, config), std::move(ranks), config);
}

void OnlineBreakFinder::start_session() {
  begin_ = frames_;
  last_time_.reset();
  intervals_.clear();
  previous_.clear();
  step_ranks_.clear();
}

std::optional<OnlineBreakFinder::Gap> OnlineBreakFinder::add(std::optional<double> time,
                                                             const std::vector<std::vector<float>>& rows) {
  for (const auto& row : rows) {
    if (row.size() != frames_) {
      throw std::invalid_argument("a row of " + std::to_string(row.size()) + " similarities for frame " +
                                  std::to_string(frames_));
    }
  }
  const std::size_t t = frames_++;
  // A session without times has no gap: none of the work below (the step ranks, the rows kept) is needed.
  if (!time) {
    previous_.clear();
    return std::nullopt;
  }
  check_time(t, *time, last_time_);
  // The step (t - 1, t) ranked, by each descriptor, against the session's frames before both.
  std::vector<double> ranks;
  if (t > begin_ + 1 && previous_.size() == rows.size()) {
    const std::size_t others = t - 1 - begin_;
    for (std::size_t d = 0; d < rows.size(); ++d) {
      const float s = rows[d][t - 1];
      std::size_t below_t = 0, below_previous = 0;
      for (std::size_t j = begin_; j + 1 < t; ++j) {
        below_t += rows[d][j] < s ? 1 : 0;
        below_previous += previous_[d][j] < s ? 1 : 0;
      }
      ranks.push_back(static_cast<double>(std::min(below_t, below_previous)) / static_cast<double>(others));
    }
  }
  std::optional<Gap> gap;
  if (last_time_) {
    const double interval = *time - *last_time_;
    // By the intervals before this one (at least two), as time_gaps rules on the whole recording.
    if (intervals_.size() >= 2 && is_gap(interval, intervals_.median(), config_)) {
      bool neighbours = false;
      for (std::size_t d = 0; d < ranks.size() && d < step_ranks_.size(); ++d) {
        neighbours = neighbours || ranks_as_neighbours(ranks[d], step_ranks_[d], config_);
      }
      gap = Gap{{t, interval, intervals_.median()}, !neighbours};
    }
    intervals_.add(interval);
  }
  last_time_ = time;
  if (!gap) {  // a gap's step is not one of the recording's own
    if (step_ranks_.size() < ranks.size()) step_ranks_.resize(ranks.size());
    for (std::size_t d = 0; d < ranks.size(); ++d) step_ranks_[d].push_back(ranks[d]);
  }
  previous_ = rows;
  return gap;
}

}  // namespace seqtopo::timeline
