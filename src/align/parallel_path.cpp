#include "seqtopo/align/parallel_path.hpp"

#include <cstdint>
#include <vector>

namespace seqtopo::align {

LocalAlignment best_parallel_path(const LocalAlignment& alignment, const ScoreSource& scores, const AlignConfig& search,
                                  std::size_t reach) {
  if (alignment.pairs.empty() || reach == 0) return alignment;
  const auto r = static_cast<std::int64_t>(reach);
  const auto cols = static_cast<std::int64_t>(scores.cols());
  const auto sep = static_cast<std::int64_t>(search.min_separation);
  std::vector<double> sums(2 * reach + 1, 0.0);
  std::vector<bool> inside(2 * reach + 1, true);
  std::vector<Score> row(2 * reach + 1);
  for (const auto& [i, j] : alignment.pairs) {
    const auto ii = static_cast<std::int64_t>(i), jj = static_cast<std::int64_t>(j);
    for (std::int64_t d = -r; d <= r; ++d) {
      const std::int64_t c = jj + d;
      auto slot = static_cast<std::size_t>(d + r);
      if (c < 0 || c >= cols || (search.self && ii - c < sep)) inside[slot] = false;
    }
    // One row segment per pair: the cells beside it that are in the matrix.
    const std::int64_t lo = std::max<std::int64_t>(0, jj - r), hi = std::min<std::int64_t>(cols, jj + r + 1);
    scores.read_row(i, static_cast<std::size_t>(lo), static_cast<std::size_t>(hi), row.data());
    for (std::int64_t c = lo; c < hi; ++c)
      sums[static_cast<std::size_t>(c - jj + r)] += row[static_cast<std::size_t>(c - lo)];
  }
  std::int64_t best = 0;
  for (std::int64_t step = 1; step <= r; ++step) {
    for (const std::int64_t d : {-step, step}) {
      const auto slot = static_cast<std::size_t>(d + r);
      if (inside[slot] && sums[slot] > sums[static_cast<std::size_t>(best + r)]) best = d;
    }
  }
  if (best == 0) return alignment;
  LocalAlignment out = alignment;
  for (auto& [i, j] : out.pairs) j = static_cast<std::size_t>(static_cast<std::int64_t>(j) + best);
  out.b_begin = static_cast<std::size_t>(static_cast<std::int64_t>(alignment.b_begin) + best);
  out.b_end = static_cast<std::size_t>(static_cast<std::int64_t>(alignment.b_end) + best);
  return out;
}

}  // namespace seqtopo::align
