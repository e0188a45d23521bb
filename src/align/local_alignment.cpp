#include "seqtopo/align/local_alignment.hpp"

#include <algorithm>
#include <stdexcept>

namespace seqtopo::align {

LocalAlignment pairs_between(const LocalAlignment& alignment, std::size_t first, std::size_t last) {
  if (first > last || last >= alignment.pairs.size()) throw std::invalid_argument("pairs_between: no such pairs");
  LocalAlignment out = alignment;
  out.pairs.assign(alignment.pairs.begin() + static_cast<std::ptrdiff_t>(first),
                   alignment.pairs.begin() + static_cast<std::ptrdiff_t>(last) + 1);
  out.a_begin = out.pairs.front().first;
  out.a_end = out.pairs.back().first + 1;
  const auto [low, high] = std::minmax_element(out.pairs.begin(), out.pairs.end(),
                                               [](const auto& x, const auto& y) { return x.second < y.second; });
  out.b_begin = low->second;
  out.b_end = high->second + 1;
  return out;
}

double path_score(const LocalAlignment& a, const ScoreSource& scores, double gap_a, double gap_b) {
  double total = 0;
  for (std::size_t k = 0; k < a.pairs.size(); ++k) {
    const auto [i, j] = a.pairs[k];
    total += scores.at(i, j);
    if (k == 0) continue;
    const auto [pi, pj] = a.pairs[k - 1];
    const std::size_t skipped_a = i - pi - 1;
    const std::size_t skipped_b = (j > pj ? j - pj : pj - j) - 1;
    total -= gap_a * static_cast<double>(skipped_a) + gap_b * static_cast<double>(skipped_b);
  }
  return total;
}

}  // namespace seqtopo::align
