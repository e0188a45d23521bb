#include "seqtopo/strings/banded_global_alignment.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace seqtopo::strings {
namespace {

using Index = std::int64_t;

struct Cell {
  double cost = std::numeric_limits<double>::infinity();
  std::size_t differences = 0;
  bool reachable() const { return cost != std::numeric_limits<double>::infinity(); }
};

// Lexicographic order: cost, then number of differences.
bool better(const Cell& a, const Cell& b) {
  return a.cost < b.cost || (a.cost == b.cost && a.differences < b.differences);
}

Cell step(const Cell& from, double cost, bool difference) {
  if (!from.reachable()) return {};
  return {from.cost + cost, from.differences + (difference ? 1 : 0)};
}

// Smallest cost of any path from (i, j) to (n, m): x diagonal steps plus the remaining indels, linear in
// x, so the minimum is at one end.
double remaining_lower_bound(Index rows_left, Index cols_left, const EditCosts& c, double diag_min) {
  const Index x = std::min(rows_left, cols_left);
  const double none = static_cast<double>(rows_left) * c.deletion + static_cast<double>(cols_left) * c.insertion;
  const double most = static_cast<double>(x) * diag_min + static_cast<double>(rows_left - x) * c.deletion +
                      static_cast<double>(cols_left - x) * c.insertion;
  return std::min(none, most);
}

}  // namespace

namespace detail {

GlobalAlignment banded_global_alignment_bounded(std::string_view pattern, std::string_view text,
                                                const GlobalAlignmentConfig& config, double abandon_above) {
  const EditCosts& c = config.costs;
  validate(c);
  const Index n = static_cast<Index>(pattern.size()), m = static_cast<Index>(text.size());
  const Index delta = m - n;
  // Band of diagonals d = j - i with |d| + |d - delta| <= k, clipped to the table.
  Index lo = -n, hi = m;
  if (config.k != kNoLimit) {
    const Index k = static_cast<Index>(std::min<std::size_t>(config.k, static_cast<std::size_t>(n + m)));
    if (std::abs(delta) > k) return {};  // more than k indels are unavoidable
    lo = std::max(lo, static_cast<Index>(std::ceil(static_cast<double>(delta - k) / 2.0)));
    hi = std::min(hi, static_cast<Index>(std::floor(static_cast<double>(delta + k) / 2.0)));
  }
  const Index width = hi - lo + 1;
  std::vector<Cell> band(static_cast<std::size_t>((n + 1) * width));
  auto at = [&](Index i, Index j) -> Cell& { return band[static_cast<std::size_t>(i * width + (j - i - lo))]; };
  auto in_band = [&](Index i, Index j) { return j >= 0 && j <= m && j - i >= lo && j - i <= hi; };
  auto get = [&](Index i, Index j) -> Cell { return in_band(i, j) ? at(i, j) : Cell{}; };

  const bool bounded = abandon_above != std::numeric_limits<double>::infinity();
  const double diag_min = c.min_diagonal_cost();
  // Rounding in the lower bound must never abandon a row that could still tie the best.
  const double slack = 1e-9 * (1.0 + std::abs(abandon_above));

  for (Index i = 0; i <= n; ++i) {
    const Index j_begin = std::max<Index>(0, i + lo), j_end = std::min<Index>(m, i + hi);
    double row_bound = std::numeric_limits<double>::infinity();
    for (Index j = j_begin; j <= j_end; ++j) {
      Cell best;
      if (i == 0 && j == 0) {
        best = {0.0, 0};
      } else {
        if (i > 0 && j > 0) {
          const bool same = pattern[static_cast<std::size_t>(i - 1)] == text[static_cast<std::size_t>(j - 1)];
          best = step(get(i - 1, j - 1),
                      c.substitution(pattern[static_cast<std::size_t>(i - 1)], text[static_cast<std::size_t>(j - 1)]),
                      !same);
        }
        if (i > 0) {
          const Cell del = step(get(i - 1, j), c.deletion, true);
          if (better(del, best)) best = del;
        }
        if (j > 0) {
          const Cell ins = step(get(i, j - 1), c.insertion, true);
          if (better(ins, best)) best = ins;
        }
      }
      at(i, j) = best;
      if (bounded && best.reachable()) {
        row_bound = std::min(row_bound, best.cost + remaining_lower_bound(n - i, m - j, c, diag_min));
      }
    }
    if (bounded && row_bound > abandon_above + slack) return {};
  }

  const Cell end = get(n, m);
  GlobalAlignment result;
  if (!end.reachable()) return result;
  result.cost = end.cost;
  result.differences = end.differences;
  result.within_k = config.k == kNoLimit || end.differences <= config.k;
  if (!config.want_path) return result;

  // Traceback: any predecessor that reproduces the cell exactly lies on an optimal path.
  std::string path;
  Index i = n, j = m;
  while (i > 0 || j > 0) {
    const Cell here = at(i, j);
    auto same = [&](const Cell& a) {
      return a.reachable() && a.cost == here.cost && a.differences == here.differences;
    };
    if (i > 0 && j > 0) {
      const char p = pattern[static_cast<std::size_t>(i - 1)], t = text[static_cast<std::size_t>(j - 1)];
      if (same(step(get(i - 1, j - 1), c.substitution(p, t), p != t))) {
        path.push_back(p == t ? '=' : 'X');
        --i, --j;
        continue;
      }
    }
    if (i > 0 && same(step(get(i - 1, j), c.deletion, true))) {
      path.push_back('D');
      --i;
      continue;
    }
    path.push_back('I');
    --j;
  }
  std::reverse(path.begin(), path.end());
  result.path = std::move(path);
  return result;
}

}  // namespace detail

GlobalAlignment banded_global_alignment(std::string_view pattern, std::string_view text,
                                        const GlobalAlignmentConfig& config) {
  return detail::banded_global_alignment_bounded(pattern, text, config, std::numeric_limits<double>::infinity());
}

}  // namespace seqtopo::strings
