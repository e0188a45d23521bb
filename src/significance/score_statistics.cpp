#include "seqtopo/significance/score_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace seqtopo::significance {

double ScoreStatistics::e_value(double score) const {
  if (!valid()) return std::numeric_limits<double>::quiet_NaN();
  return k * area * std::exp(-lambda * score);
}

double ScoreStatistics::bit_score(double score) const {
  if (!valid()) return std::numeric_limits<double>::quiet_NaN();
  return (lambda * score - std::log(k)) / std::log(2.0);
}

double ScoreStatistics::score_at(double e) const {
  if (!valid() || !(e > 0)) return std::numeric_limits<double>::quiet_NaN();
  return std::log(k * area / e) / lambda;
}

namespace {

// Least squares of ln(rank) = a - lambda * score over ranks [first, scores.size()] (1-based).
ScoreStatistics line_fit(std::span<const double> scores, double area, std::size_t first, std::size_t min_fitted) {
  ScoreStatistics s;
  s.area = area;
  if (first < 1) first = 1;
  if (scores.size() < first || scores.size() - first + 1 < min_fitted) return s;
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const std::size_t n = scores.size() - first + 1;
  for (std::size_t r = first; r <= scores.size(); ++r) {
    const double x = scores[r - 1], y = std::log(static_cast<double>(r));
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  const double count = static_cast<double>(n);
  const double var = sxx - sx * sx / count;
  if (!(var > 0)) return s;
  const double slope = (sxy - sx * sy / count) / var;
  if (!(slope < 0)) return s;
  s.lambda = -slope;
  const double intercept = (sy - slope * sx) / count;  // ln(K * area)
  s.k = std::exp(intercept) / area;
  s.fitted = n;
  s.first_fitted_rank = first;
  return s;
}

}  // namespace

ScoreStatistics fit_declumped_scores(std::span<const double> scores, double area, const FitConfig& config) {
  if (!(area > 0)) return {};
  for (std::size_t k = 1; k < scores.size(); ++k) {
    if (!(scores[k] <= scores[k - 1])) throw std::invalid_argument("alignment scores must be best first");
  }
  ScoreStatistics fit = line_fit(scores, area, config.first_rank, config.min_fitted);
  if (!fit.valid()) return fit;
  // Real alignments are far above the chance line: refit after setting them aside.
  std::size_t real = 0;
  while (real < scores.size() && fit.e_value(scores[real]) < config.real_e_value) ++real;
  const std::size_t first = std::max(config.first_rank, 2 * real + 1);
  if (first != config.first_rank) {
    const ScoreStatistics refit = line_fit(scores, area, first, config.min_fitted);
    if (refit.valid()) return refit;
  }
  return fit;
}

double path_score(const align::LocalAlignment& a, const align::ScoreSource& scores, double gap_a, double gap_b) {
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

double search_area(std::size_t rows, std::size_t cols, bool self, std::size_t min_separation, bool both_passes) {
  double cells = 0;
  if (self) {
    // pairs (i, j) with i - j >= s: sum over i >= s of (i - s + 1), i < rows
    const double n = static_cast<double>(rows), s = static_cast<double>(std::max<std::size_t>(min_separation, 1));
    cells = n >= s ? (n - s) * (n - s + 1) / 2 : 0;
  } else {
    cells = static_cast<double>(rows) * static_cast<double>(cols);
  }
  return both_passes ? 2 * cells : cells;
}

}  // namespace seqtopo::significance
