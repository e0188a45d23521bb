#include "seqtopo/significance/alignment_phase.hpp"

#include <algorithm>
#include <random>
#include <stdexcept>
#include <vector>

namespace seqtopo::significance {

double global_alignment_rate(std::span<const float> cells, std::size_t n, float gap) {
  if (n == 0 || cells.size() != n * n) throw std::invalid_argument("global alignment: the table must be n x n, n > 0");
  std::vector<double> row(n + 1), next(n + 1);
  for (std::size_t j = 0; j <= n; ++j) row[j] = -static_cast<double>(j) * gap;
  for (std::size_t i = 1; i <= n; ++i) {
    next[0] = -static_cast<double>(i) * gap;
    for (std::size_t j = 1; j <= n; ++j) {
      next[j] = std::max({row[j - 1] + cells[(i - 1) * n + (j - 1)], row[j] - gap, next[j - 1] - gap});
    }
    std::swap(row, next);
  }
  return row[n] / static_cast<double>(n);
}

double resampled_global_rate(std::span<const float> scores, std::size_t n, float gap, std::uint64_t seed) {
  if (scores.empty() || n == 0) throw std::invalid_argument("global alignment rate: no scores to draw from");
  std::mt19937_64 rng(seed);  // its sequence is fixed by the standard; the modulo keeps the draw portable
  std::vector<float> cells(n * n);
  for (auto& c : cells) c = scores[rng() % scores.size()];
  return global_alignment_rate(cells, n, gap);
}

}  // namespace seqtopo::significance
