#include "seqtopo/align/band_realignment.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace seqtopo::align {
namespace {

constexpr double kNone = -std::numeric_limits<double>::infinity();

}  // namespace

LocalAlignment realign_in_band(const LocalAlignment& alignment, const ScoreSource& scores, const AlignConfig& search,
                               std::size_t reach) {
  if (alignment.pairs.size() < 2 || reach == 0) return alignment;
  const bool reverse = alignment.direction == Direction::reverse;
  const auto cols = static_cast<std::int64_t>(scores.cols());
  const auto r = static_cast<std::int64_t>(reach);
  const std::size_t width = 2 * reach + 1;
  const std::size_t first = alignment.pairs.front().first, last = alignment.pairs.back().first;
  const std::size_t rows = last - first + 1;
  // In pass columns t (t = j forward, cols - 1 - j reverse) every path runs right and down, as forward.
  const auto pass = [&](std::size_t j) {
    return reverse ? cols - 1 - static_cast<std::int64_t>(j) : static_cast<std::int64_t>(j);
  };
  std::vector<std::int64_t> centre(rows);
  for (std::size_t k = 0, row = 0; row < rows; ++row) {
    while (k + 1 < alignment.pairs.size() && alignment.pairs[k + 1].first <= first + row) ++k;
    centre[row] = pass(alignment.pairs[k].second);
  }
  const double gap_a = search.gap_a, gap_b = search.gap_b;
  // Per band cell: the best path ending in a pair there (d) and ending there by any step (h), with h's step.
  std::vector<double> d(rows * width, kNone), h(rows * width, kNone);
  std::vector<std::uint8_t> step(rows * width, 0);  // 0 pair, 1 from above, 2 from the left
  std::vector<Score> cells(width);
  const auto at = [&](std::size_t row, std::int64_t t) -> std::int64_t {  // band index or -1
    const std::int64_t k = t - (centre[row] - r);
    return k < 0 || k >= static_cast<std::int64_t>(width) ? -1 : static_cast<std::int64_t>(row * width) + k;
  };
  for (std::size_t row = 0; row < rows; ++row) {
    const std::size_t i = first + row;
    const std::int64_t lo = std::max<std::int64_t>(0, centre[row] - r), hi = std::min(cols - 1, centre[row] + r);
    if (lo > hi) continue;
    // The row segment in original columns, read once.
    const std::int64_t j_lo = reverse ? cols - 1 - hi : lo, j_hi = reverse ? cols - 1 - lo : hi;
    scores.read_row(i, static_cast<std::size_t>(j_lo), static_cast<std::size_t>(j_hi + 1), cells.data());
    for (std::int64_t t = lo; t <= hi; ++t) {
      const std::int64_t j = reverse ? cols - 1 - t : t;
      if (search.self && static_cast<std::int64_t>(i) - j < static_cast<std::int64_t>(search.min_separation)) continue;
      const auto here = static_cast<std::size_t>(at(row, t));
      const double cell = cells[static_cast<std::size_t>(j - j_lo)];
      if (row == 0) {
        d[here] = cell;
      } else if (const std::int64_t from = at(row - 1, t - 1); from >= 0 && h[static_cast<std::size_t>(from)] > kNone) {
        d[here] = cell + h[static_cast<std::size_t>(from)];
      }
      double best = d[here];
      std::uint8_t how = 0;
      if (row > 0) {
        if (const std::int64_t up = at(row - 1, t); up >= 0 && h[static_cast<std::size_t>(up)] - gap_a > best) {
          best = h[static_cast<std::size_t>(up)] - gap_a;
          how = 1;
        }
      }
      if (const std::int64_t left = at(row, t - 1); left >= 0 && h[static_cast<std::size_t>(left)] - gap_b > best) {
        best = h[static_cast<std::size_t>(left)] - gap_b;
        how = 2;
      }
      h[here] = best;
      step[here] = how;
    }
  }
  // The end: a pair in the last row, the best, nearest the engine's end on ties (its left first).
  const std::size_t end_row = rows - 1;
  std::int64_t end = -1;
  for (std::int64_t off = 0; off <= r; ++off) {
    for (const std::int64_t t : {centre[end_row] - off, centre[end_row] + off}) {
      const std::int64_t k = at(end_row, t);
      if (k >= 0 && d[static_cast<std::size_t>(k)] > kNone &&
          (end < 0 || d[static_cast<std::size_t>(k)] > d[static_cast<std::size_t>(end)])) {
        end = k;
      }
      if (off == 0) break;
    }
  }
  if (end < 0) return alignment;
  if (d[static_cast<std::size_t>(end)] <= path_score(alignment, scores, gap_a, gap_b) + 1e-9) return alignment;
  LocalAlignment out = alignment;
  out.pairs.clear();
  std::size_t row = end_row;
  std::int64_t t = centre[end_row] - r + (end - static_cast<std::int64_t>(end_row * width));
  bool in_pair = true;  // the end is a pair (the d state)
  while (true) {
    const auto k = static_cast<std::size_t>(at(row, t));
    if (in_pair || step[k] == 0) {
      out.pairs.emplace_back(first + row, static_cast<std::size_t>(reverse ? cols - 1 - t : t));
      if (row == 0) break;
      --row;
      --t;
      in_pair = false;
    } else if (step[k] == 1) {
      --row;
    } else {
      --t;
    }
  }
  std::reverse(out.pairs.begin(), out.pairs.end());
  return pairs_between(out, 0, out.pairs.size() - 1);
}

}  // namespace seqtopo::align
