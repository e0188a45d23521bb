#include "seqtopo/align/pair_posterior.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace seqtopo::align {
namespace {

constexpr double kNone = -std::numeric_limits<double>::infinity();

double log_add(double a, double b) {
  if (a == kNone) return b;
  if (b == kNone) return a;
  const double m = std::max(a, b);
  return m + std::log1p(std::exp(-std::abs(a - b)));
}

// The band: rows [first, first + rows) of A, and in row r the columns u in [low[r], low[r] + width) of B in
// path order (u = j forward, cols - 1 - j reverse), each cell with three states (match, skip in A, skip in B).
class Band {
 public:
  Band(std::size_t first, std::size_t rows, std::size_t width, std::vector<std::ptrdiff_t> low)
      : first_(first), rows_(rows), width_(width), low_(std::move(low)), values_(rows * width * 3, kNone) {}
  // The cell's index, or npos when (r, u) is outside the band.
  std::size_t index(std::size_t r, std::ptrdiff_t u) const {
    if (r >= rows_ || u < low_[r] || u >= low_[r] + static_cast<std::ptrdiff_t>(width_)) return npos;
    return (r * width_ + static_cast<std::size_t>(u - low_[r])) * 3;
  }
  double get(std::size_t r, std::ptrdiff_t u, int state) const {
    const std::size_t k = index(r, u);
    return k == npos ? kNone : values_[k + static_cast<std::size_t>(state)];
  }
  double& at(std::size_t k, int state) { return values_[k + static_cast<std::size_t>(state)]; }
  std::ptrdiff_t low(std::size_t r) const { return low_[r]; }
  std::size_t rows() const { return rows_; }
  std::size_t width() const { return width_; }
  std::size_t first() const { return first_; }
  static constexpr std::size_t npos = static_cast<std::size_t>(-1);

 private:
  std::size_t first_, rows_, width_;
  std::vector<std::ptrdiff_t> low_;
  std::vector<double> values_;
};

enum State { M = 0, X = 1, Y = 2 };

// The forward and backward tables of one alignment's band, and the readouts.
struct BandTables {
  Band f, b;
  double total;
  std::size_t first;
  bool reverse;
  std::size_t cols;
  std::ptrdiff_t to_u(std::size_t j) const { return static_cast<std::ptrdiff_t>(reverse ? cols - 1 - j : j); }
  std::size_t to_j(std::ptrdiff_t u) const {
    return static_cast<std::size_t>(reverse ? static_cast<std::ptrdiff_t>(cols) - 1 - u : u);
  }
  // Posterior that row `first + r` is aligned to a path column within +-t of u; with `skipped`, also that the
  // chain passes the row there skipping it (state X: the row between two matched ones, at the column of the
  // one before).
  double posterior(std::size_t r, std::ptrdiff_t u, std::size_t t, bool skipped = false) const {
    // Only the band's columns of the row hold probability: the window is clipped to them, so the cost is the
    // band's width whatever the tolerance (--tolerance 4294967295 is as fast as 2).
    const auto width = static_cast<std::ptrdiff_t>(f.width());
    const std::ptrdiff_t reach = static_cast<std::ptrdiff_t>(std::min<std::size_t>(t, f.width() + cols));
    const std::ptrdiff_t lo = std::max(u - reach, f.low(r)), hi = std::min(u + reach, f.low(r) + width - 1);
    double sum = 0;
    for (std::ptrdiff_t v = lo; v <= hi; ++v) {
      for (int state : {M, X}) {
        if (state == X && !skipped) break;
        const double fw = f.get(r, v, state), bw = b.get(r, v, state);
        if (fw != kNone && bw != kNone) sum += std::exp(fw + bw - total);
      }
    }
    return std::clamp(sum, 0.0, 1.0);
  }
};

BandTables band_tables(const LocalAlignment& a, const ScoreSource& scores, const PosteriorConfig& c) {
  if (!(c.lambda > 0) || !std::isfinite(c.lambda)) throw std::invalid_argument("posterior: lambda must be positive");
  const std::size_t n_rows = scores.rows(), n_cols = scores.cols();
  for (auto [i, j] : a.pairs) {
    if (i >= n_rows || j >= n_cols) {
      throw std::invalid_argument("posterior: pair (" + std::to_string(i) + ", " + std::to_string(j) +
                                  ") outside the scores");
    }
  }
  const bool reverse = a.direction == Direction::reverse;
  const auto to_u = [&](std::size_t j) { return static_cast<std::ptrdiff_t>(reverse ? n_cols - 1 - j : j); };
  const auto to_j = [&](std::ptrdiff_t u) { return static_cast<std::size_t>(reverse ? n_cols - 1 - u : u); };
  const std::size_t i_first = a.pairs.front().first, i_last = a.pairs.back().first;
  const std::size_t first = i_first >= c.band ? i_first - c.band : 0;
  const std::size_t last = std::min(n_rows - 1, i_last + c.band);
  const std::size_t rows = last - first + 1;
  const auto band = static_cast<std::ptrdiff_t>(c.band);
  // The path's column in every row: its pair's, carried along gaps, extended diagonally beyond the ends.
  std::vector<std::ptrdiff_t> low(rows);
  std::size_t next = 0;
  for (std::size_t r = 0; r < rows; ++r) {
    const std::size_t i = first + r;
    while (next + 1 < a.pairs.size() && a.pairs[next + 1].first <= i) ++next;
    const auto [pi, pj] = a.pairs[next];
    const std::ptrdiff_t centre = to_u(pj) + (static_cast<std::ptrdiff_t>(i) - static_cast<std::ptrdiff_t>(pi));
    low[r] = centre - band;
  }
  Band f(first, rows, 2 * c.band + 1, low), b(first, rows, 2 * c.band + 1, std::move(low));
  const double gap_a = -c.lambda * c.gap_a, gap_b = -c.lambda * c.gap_b;
  const auto allowed = [&](std::size_t i, std::ptrdiff_t u) {
    if (u < 0 || u >= static_cast<std::ptrdiff_t>(n_cols)) return false;
    const std::size_t j = to_j(u);
    return !c.self || (i > j && i - j >= std::max<std::size_t>(c.min_separation, 1));
  };
  // The band's scores, read once row by row (a row segment: a streamed similarity computes cached tiles, where
  // cell by cell it would sum each cell's contrast windows anew, twice, for the forward and backward passes).
  std::vector<Score> band_scores(rows * f.width());
  std::vector<Score> segment;
  for (std::size_t r = 0; r < rows; ++r) {
    const std::ptrdiff_t u0 = std::max<std::ptrdiff_t>(f.low(r), 0);
    const std::ptrdiff_t u1 = std::min<std::ptrdiff_t>(f.low(r) + static_cast<std::ptrdiff_t>(f.width()),
                                                       static_cast<std::ptrdiff_t>(n_cols));
    if (u1 <= u0) continue;
    const std::size_t j0 = std::min(to_j(u0), to_j(u1 - 1)), j1 = std::max(to_j(u0), to_j(u1 - 1)) + 1;
    segment.resize(j1 - j0);
    scores.read_row(first + r, j0, j1, segment.data());
    for (std::ptrdiff_t u = u0; u < u1; ++u)
      band_scores[r * f.width() + static_cast<std::size_t>(u - f.low(r))] = segment[to_j(u) - j0];
  }
  const auto weight = [&](std::size_t i, std::ptrdiff_t u) {
    const std::size_t r = i - first;
    return c.lambda * band_scores[r * f.width() + static_cast<std::size_t>(u - f.low(r))];
  };

  // Forward: the weight of every chain ending in each state of the cell.
  double total = 0;  // log of the empty chain's weight, 1
  for (std::size_t r = 0; r < rows; ++r) {
    const std::size_t i = first + r;
    for (std::size_t w = 0; w < f.width(); ++w) {
      const std::ptrdiff_t u = f.low(r) + static_cast<std::ptrdiff_t>(w);
      const std::size_t k = f.index(r, u);
      if (!allowed(i, u)) continue;
      double into = 0;  // a chain may start here
      double x = kNone;
      if (r > 0) {
        into = log_add(into, log_add(f.get(r - 1, u - 1, M), log_add(f.get(r - 1, u - 1, X), f.get(r - 1, u - 1, Y))));
        x = gap_a + log_add(f.get(r - 1, u, M), f.get(r - 1, u, X));
      }
      f.at(k, M) = weight(i, u) + into;
      f.at(k, X) = x;
      f.at(k, Y) = gap_b + log_add(f.get(r, u - 1, M), log_add(f.get(r, u - 1, X), f.get(r, u - 1, Y)));
      total = log_add(total, f.at(k, M));
    }
  }
  // Backward: the weight of every continuation after each state of the cell.
  for (std::size_t r = rows; r-- > 0;) {
    const std::size_t i = first + r;
    for (std::size_t w = b.width(); w-- > 0;) {
      const std::ptrdiff_t u = b.low(r) + static_cast<std::ptrdiff_t>(w);
      const std::size_t k = b.index(r, u);
      if (!allowed(i, u)) continue;
      double match_next = kNone, x_next = kNone;
      if (r + 1 < rows) {
        const double bm = b.get(r + 1, u + 1, M);
        if (bm != kNone) match_next = weight(i + 1, u + 1) + bm;
        x_next = gap_a + b.get(r + 1, u, X);
      }
      const double y_next = gap_b + b.get(r, u + 1, Y);
      b.at(k, M) = log_add(0.0, log_add(match_next, log_add(x_next, y_next)));
      b.at(k, X) = log_add(match_next, log_add(x_next, y_next));
      b.at(k, Y) = log_add(match_next, y_next);
    }
  }
  return BandTables{std::move(f), std::move(b), total, first, reverse, n_cols};
}

}  // namespace

std::vector<double> pair_posteriors(const LocalAlignment& a, const ScoreSource& scores, const PosteriorConfig& c) {
  if (a.pairs.empty()) {
    if (!(c.lambda > 0) || !std::isfinite(c.lambda)) throw std::invalid_argument("posterior: lambda must be positive");
    return {};
  }
  const BandTables t = band_tables(a, scores, c);
  std::vector<double> posterior;
  posterior.reserve(a.pairs.size());
  for (auto [i, j] : a.pairs) posterior.push_back(t.posterior(i - t.first, t.to_u(j), c.tolerance));
  return posterior;
}

std::vector<RowPosterior> row_posteriors(const LocalAlignment& a, const ScoreSource& scores, const PosteriorConfig& c) {
  if (a.pairs.empty()) {
    if (!(c.lambda > 0) || !std::isfinite(c.lambda)) throw std::invalid_argument("posterior: lambda must be positive");
    return {};
  }
  const BandTables t = band_tables(a, scores, c);
  std::vector<RowPosterior> out;
  out.reserve(t.f.rows());
  for (std::size_t r = 0; r < t.f.rows(); ++r) {
    // The most probable cell of the row (the first of equals in path order), and the posterior within
    // +-tolerance of it.
    std::ptrdiff_t best = 0;
    double best_cell = -1;
    for (std::size_t w = 0; w < t.f.width(); ++w) {
      const std::ptrdiff_t u = t.f.low(r) + static_cast<std::ptrdiff_t>(w);
      if (u < 0 || u >= static_cast<std::ptrdiff_t>(t.cols) || t.f.get(r, u, M) == kNone) continue;
      const double p = t.posterior(r, u, 0, true);
      if (p > best_cell) best_cell = p, best = u;
    }
    if (best_cell >= 0) out.push_back({t.first + r, t.to_j(best), t.posterior(r, best, c.tolerance, true)});
  }
  return out;
}

}  // namespace seqtopo::align
