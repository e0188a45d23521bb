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

}  // namespace

std::vector<TimeGap> time_gaps(std::span<const double> times, const SessionBreakConfig& config) {
  for (std::size_t k = 0; k < times.size(); ++k) {
    if (!std::isfinite(times[k])) throw std::invalid_argument("frame time " + std::to_string(k) + " is not finite");
    if (k > 0 && times[k] < times[k - 1]) {
      throw std::invalid_argument("frame times decrease at frame " + std::to_string(k));
    }
  }
  if (times.size() < 3) return {};
  std::vector<double> intervals;
  intervals.reserve(times.size() - 1);
  for (std::size_t k = 1; k < times.size(); ++k) intervals.push_back(times[k] - times[k - 1]);
  std::vector<double> sorted = intervals;
  const auto middle = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), middle, sorted.end());
  const double median = *middle;
  if (!(median > 0)) return {};
  std::vector<TimeGap> gaps;
  for (std::size_t k = 0; k < intervals.size(); ++k) {
    if (intervals[k] >= config.gap_factor * median && intervals[k] >= config.min_gap) {
      gaps.push_back({k + 1, intervals[k], median});
    }
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
  std::sort(ranks.begin(), ranks.end());
  const auto at = static_cast<std::size_t>(config.neighbour_quantile * static_cast<double>(ranks.size() - 1));
  return neighbour_rank(similarity, a, b, begin, end, config) >= std::max(ranks[at], config.min_neighbour_rank);
}

}  // namespace seqtopo::timeline
