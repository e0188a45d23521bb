#include "seqtopo/significance/alignment_ends.hpp"

#include <algorithm>
#include <vector>

namespace seqtopo::significance {

align::LocalAlignment trim_chance_ends(const align::LocalAlignment& alignment, const align::ScoreSource& scores,
                                       double gap_a, double gap_b, double chance_mean, double max_tail_gain) {
  const auto& pairs = alignment.pairs;
  const std::size_t n = pairs.size();
  if (n < 3) return alignment;
  std::vector<double> cell(n);
  double mean = 0;
  for (std::size_t p = 0; p < n; ++p) {
    cell[p] = scores.at(pairs[p].first, pairs[p].second);
    mean += cell[p];
  }
  mean /= static_cast<double>(n);
  if (!(mean > chance_mean)) return alignment;
  const double midpoint = (chance_mean + mean) / 2;
  // gap[p]: the penalty of the elements skipped between pairs p - 1 and p.
  std::vector<double> gap(n, 0.0);
  for (std::size_t p = 1; p < n; ++p) {
    const std::size_t di = pairs[p].first - pairs[p - 1].first;
    const std::size_t dj = pairs[p].second > pairs[p - 1].second ? pairs[p].second - pairs[p - 1].second
                                                                 : pairs[p - 1].second - pairs[p].second;
    gap[p] = gap_a * static_cast<double>(di > 0 ? di - 1 : 0) + gap_b * static_cast<double>(dj > 0 ? dj - 1 : 0);
  }
  // The end: where the cumulative (score - midpoint) minus gaps, summed from the start, peaks (the latest of
  // equal peaks). The tail after it goes only when its own score is one a chance extension often reaches.
  std::size_t hi = n - 1;
  {
    double lowered = 0, best = 0;
    std::size_t end = 0;
    for (std::size_t p = 0; p < n; ++p) {
      lowered += cell[p] - midpoint - gap[p];
      if (p == 0 || lowered >= best) best = lowered, end = p;
    }
    double tail = 0;
    for (std::size_t p = end + 1; p < n; ++p) tail += cell[p] - gap[p];
    if (tail < max_tail_gain) hi = end;
  }
  // The start likewise, summed from the end (the earliest of equal peaks).
  std::size_t lo = 0;
  {
    double lowered = 0, best = 0;
    std::size_t start = n - 1;
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t p = n - 1 - k;
      lowered += cell[p] - midpoint - (p + 1 < n ? gap[p + 1] : 0.0);
      if (k == 0 || lowered >= best) best = lowered, start = p;
    }
    double head = 0;
    for (std::size_t p = 0; p < start; ++p) head += cell[p] - gap[p + 1];
    if (head < max_tail_gain) lo = start;
  }
  if (lo > hi || (lo == 0 && hi == n - 1)) return alignment;
  return align::pairs_between(alignment, lo, hi);
}

}  // namespace seqtopo::significance
