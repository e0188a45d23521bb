#include "seqtopo/significance/score_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace seqtopo::significance {

double ScoreStatistics::e_value(double score) const {
  if (!valid()) return std::numeric_limits<double>::quiet_NaN();
  if (!(spacings > 0) || score <= anchor_score) return k * area * std::exp(-lambda * score);
  const double at_anchor = k * area * std::exp(-lambda * anchor_score);
  return at_anchor * std::exp(-spacings * std::log1p(lambda * (score - anchor_score) / spacings));
}

double ScoreStatistics::bit_score(double score) const {
  if (!valid()) return std::numeric_limits<double>::quiet_NaN();
  return std::log2(area / e_value(score));
}

double ScoreStatistics::score_at(double e) const {
  if (!valid() || !(e > 0)) return std::numeric_limits<double>::quiet_NaN();
  const double at_anchor = k * area * std::exp(-lambda * anchor_score);
  if (!(spacings > 0) || e >= at_anchor) return std::log(k * area / e) / lambda;
  return anchor_score + spacings / lambda * std::expm1(std::log(at_anchor / e) / spacings);
}

namespace {

// Maximum likelihood over ranks [first, M] (1-based) of the M best: in a Poisson process of intensity
// K * area * lambda * exp(-lambda s) the spacing between the r-th and (r+1)-th best scores is exponential with
// rate r * lambda, independently of the others (Renyi's representation; the Hill estimator of a tail), so
// lambda = (M - first) / sum_r r (s_r - s_{r+1}). ln(K * area) is then the mean of ln(r) + lambda s_r, the
// count above each score. Far steadier than a least-squares line through ln(rank), which the few top ranks
// swing.
// The `real` best are not chance: the chance rank of the r-th best is r - real.
ScoreStatistics tail_fit(std::span<const double> scores, double area, std::size_t first, std::size_t min_fitted,
                         std::size_t real) {
  ScoreStatistics s;
  s.area = area;
  first = std::max(first, real + 1);
  if (scores.size() < first || scores.size() - first + 1 < min_fitted) return s;
  const std::size_t m = scores.size();
  double weighted_spacings = 0;
  for (std::size_t r = first; r < m; ++r) {
    weighted_spacings += static_cast<double>(r - real) * (scores[r - 1] - scores[r]);
  }
  if (!(weighted_spacings > 0)) return s;
  s.lambda = static_cast<double>(m - first) / weighted_spacings;
  double intercept = 0;  // ln(K * area)
  double anchor = 0;
  for (std::size_t r = first; r <= m; ++r) {
    intercept += std::log(static_cast<double>(r - real)) + s.lambda * scores[r - 1];
    anchor += scores[r - 1];
  }
  intercept /= static_cast<double>(m - first + 1);
  s.k = std::exp(intercept) / area;
  s.anchor_score = anchor / static_cast<double>(m - first + 1);
  s.spacings = static_cast<double>(m - first);
  s.fitted = m - first + 1;
  s.first_fitted_rank = first;
  return s;
}

}  // namespace

ScoreStatistics fit_declumped_scores(std::span<const double> scores, double area, const FitConfig& config) {
  if (!(area > 0)) return {};
  for (std::size_t k = 1; k < scores.size(); ++k) {
    if (!(scores[k] <= scores[k - 1])) throw std::invalid_argument("alignment scores must be best first");
  }
  // The first fit on the lower three quarters, surely chance when revisits are fewer than a quarter of the
  // alignments (a longer list is asked for when they are not, map_builder.cpp): a few real ones at the top
  // would otherwise pull lambda down until they look like chance themselves.
  const std::size_t bulk = scores.size() / 4 + 1;
  ScoreStatistics fit;
  if (bulk > config.first_rank) fit = tail_fit(scores, area, bulk, config.min_fitted, 0);
  if (!fit.valid()) fit = tail_fit(scores, area, config.first_rank, config.min_fitted, 0);
  if (!fit.valid()) return fit;
  std::size_t real_before = 0;
  // Real alignments are far above the chance line: refit after setting them aside, until the set of real ones
  // stays the same (many of them pull the first fit's lambda down, which hides some of them).
  for (int round = 0; round < 8; ++round) {
    std::size_t real = 0;
    while (real < scores.size() && fit.e_value(scores[real]) < config.real_e_value) ++real;
    const std::size_t first = std::max(config.first_rank, 2 * real + 1);
    if (first == fit.first_fitted_rank && real == real_before) break;
    const ScoreStatistics refit = tail_fit(scores, area, first, config.min_fitted, real);
    if (!refit.valid()) break;
    fit = refit;
    real_before = real;
  }
  return fit;
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

double ungapped_lambda(std::span<const float> scores) {
  double mean = 0, high = 0;
  for (float v : scores) {
    mean += v;
    high = std::max(high, static_cast<double>(v));
  }
  if (scores.empty() || !(mean < 0) || !(high > 0)) return 0;
  // f(lambda) = mean(exp(lambda s)) - 1 is convex, 0 at 0 with a negative slope there, so it has one positive
  // root; bracket it by doubling, then bisect.
  const auto f = [&](double lambda) {
    double sum = 0;
    for (float v : scores) sum += std::exp(lambda * static_cast<double>(v));
    return sum / static_cast<double>(scores.size()) - 1.0;
  };
  double lo = 0, hi = 1.0 / high;
  while (f(hi) < 0) {
    lo = hi;
    hi *= 2;
    if (hi > 1e6) return 0;
  }
  for (int k = 0; k < 60; ++k) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

bool shadows_earlier(const std::vector<align::LocalAlignment>& alignments, std::size_t k, double reach) {
  const auto diagonal = [](const align::LocalAlignment& a) {
    double sum = 0;
    for (auto [i, j] : a.pairs) {
      sum += a.direction == align::Direction::forward ? static_cast<double>(i) - static_cast<double>(j)
                                                      : static_cast<double>(i + j);
    }
    return a.pairs.empty() ? 0.0 : sum / static_cast<double>(a.pairs.size());
  };
  const auto& a = alignments[k];
  const double da = diagonal(a);
  for (std::size_t e = 0; e < k; ++e) {
    const auto& b = alignments[e];
    if (b.direction != a.direction) continue;
    const std::size_t lo = std::max(a.a_begin, b.a_begin), hi = std::min(a.a_end, b.a_end);
    const std::size_t shorter = std::min(a.a_end - a.a_begin, b.a_end - b.a_begin);
    if (hi > lo && 2 * (hi - lo) >= shorter && std::abs(diagonal(b) - da) <= reach) return true;
  }
  return false;
}

double revisit_probability(double e, double even_odds) {
  if (!(even_odds > 0)) throw std::invalid_argument("revisit_probability: even_odds must be positive");
  if (!(e >= 0)) return 1.0;
  return 1.0 / (1.0 + e / even_odds);
}

}  // namespace seqtopo::significance
