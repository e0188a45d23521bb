#include "seqtopo/align/locally_optimal.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include "check_config.hpp"
#include "search_region.hpp"
#include "seqtopo/align/capped_cell.hpp"
#include "seqtopo/align/smith_waterman.hpp"

namespace seqtopo::align {

std::string_view to_string(AlignmentSet set) {
  return set == AlignmentSet::locally_optimal ? "locally-optimal" : "non-intersecting";
}

AlignmentSet parse_alignment_set(std::string_view text) {
  if (text == "locally-optimal") return AlignmentSet::locally_optimal;
  if (text == "non-intersecting") return AlignmentSet::non_intersecting;
  throw std::invalid_argument("alignment set: expected locally-optimal or non-intersecting, got '" + std::string(text) +
                              "'");
}

namespace {

constexpr Score kNegInf = -std::numeric_limits<Score>::infinity();

enum Step : std::uint8_t { none = 0, diagonal = 1, vertical = 2, horizontal = 3 };

// The scores and the searched region of one pass, in pass coordinates: vertex (i, j), 0 <= i <= m, 0 <= j <= n.
class Grid {
 public:
  Grid(const ScoreSource& scores, const AlignConfig& config)
      : config_(config), m_(scores.rows()), n_(scores.cols()), s_(m_ * n_, 0.0F), region_(m_ + 1, {1, 0}) {
    std::vector<Score> row(n_);
    for (std::size_t i = 1; i <= m_; ++i) {
      region_[i] = detail::search_region(config_, n_, i);
      const auto [lo, hi] = region_[i];
      if (lo > hi) continue;
      if (config_.direction == Direction::forward) {
        scores.read_row(i - 1, lo - 1, hi, s_.data() + (i - 1) * n_ + (lo - 1));
      } else {
        // pass columns lo..hi are original columns n-hi .. n-lo, in the opposite order
        scores.read_row(i - 1, n_ - hi, n_ - lo + 1, row.data());
        for (std::size_t j = lo; j <= hi; ++j) s_[(i - 1) * n_ + (j - 1)] = row[hi - j];
      }
    }
  }

  std::size_t rows() const { return m_; }
  std::size_t cols() const { return n_; }
  const AlignConfig& config() const { return config_; }
  // May a step enter vertex (i, j)?
  bool enterable(std::size_t i, std::size_t j) const {
    return i >= 1 && i <= m_ && j >= region_[i].first && j <= region_[i].second;
  }
  // Weight of the diagonal step into (i, j) (enterable).
  Score diagonal_weight(std::size_t i, std::size_t j) const { return s_[(i - 1) * n_ + (j - 1)]; }
  Score clamp(Score v) const { return capped(v, config_.cap); }
  std::size_t original_col(std::size_t j) const { return config_.direction == Direction::forward ? j - 1 : n_ - j; }

 private:
  AlignConfig config_;
  std::size_t m_, n_;
  std::vector<Score> s_;
  std::vector<std::pair<std::size_t, std::size_t>> region_;
};

// Vertices where the engine's table H (capped, floored at 0, no declumping) is 0: no admissible path ends there.
std::vector<std::uint8_t> zero_cells(const Grid& g) {
  const std::size_t m = g.rows(), n = g.cols();
  const AlignConfig& c = g.config();
  std::vector<std::uint8_t> zero((m + 1) * (n + 1), 1);
  std::vector<Score> prev(n + 1, 0.0F), cur(n + 1, 0.0F);
  for (std::size_t i = 1; i <= m; ++i) {
    cur[0] = 0.0F;
    for (std::size_t j = 1; j <= n; ++j) {
      const Score v = g.enterable(i, j) ? capped_cell(prev[j - 1] + g.diagonal_weight(i, j), prev[j], cur[j - 1],
                                                      c.gap_a, c.gap_b, c.cap)
                                        : 0.0F;
      cur[j] = v;
      zero[i * (n + 1) + j] = v > 0 ? 0 : 1;
    }
    std::swap(prev, cur);
  }
  return zero;
}

// Best admissible scores from one seed vertex, row by row over the band where they stay positive.
class Fill {
 public:
  struct Cell {
    Score value = kNegInf;
    Score path_max = kNegInf;  // the maximum score along the canonical path to this cell
    Step step = none;
  };
  struct Row {
    std::size_t lo = 0;  // column of cells[0]
    std::vector<Cell> cells;
    std::size_t hi() const { return lo + cells.size(); }  // one past the last column
  };

  explicit Fill(const Grid& g) : g_(g) {}

  // Seeds vertex (si, sj) with score s0 and visits every other vertex whose best admissible score is positive,
  // in row-major order: visit(i, j, cell) returns false to stop. Returns false if stopped.
  template <class Visit>
  bool run(std::size_t si, std::size_t sj, Score s0, Visit&& visit) {
    si_ = si;
    sj_ = sj;
    used_ = 0;
    Row& seed = next_row();
    seed.lo = sj;
    seed.cells.push_back({s0, s0, none});
    // Horizontal steps along the seed row.
    for (std::size_t j = sj + 1; j <= g_.cols() && g_.enterable(si, j); ++j) {
      const Score v = g_.clamp(seed.cells.back().value - g_.config().gap_b);
      if (!(v > 0)) break;
      seed.cells.push_back({v, std::max(v, seed.cells.back().path_max), horizontal});
      if (!visit(si, j, seed.cells.back())) return false;
    }
    for (std::size_t i = si + 1; i <= g_.rows(); ++i) {
      Row& cur = next_row();  // may grow rows_: take prev after it
      const Row& prev = rows_[used_ - 2];
      cur.lo = prev.lo;
      bool any = false;
      for (std::size_t j = prev.lo; j <= g_.cols(); ++j) {
        Cell c;
        if (g_.enterable(i, j)) {
          const Cell* diag = j > prev.lo && j - 1 < prev.hi() ? &prev.cells[j - 1 - prev.lo] : nullptr;
          const Cell* up = j < prev.hi() ? &prev.cells[j - prev.lo] : nullptr;
          const Cell* left = j > cur.lo ? &cur.cells.back() : nullptr;
          offer(c, diag, i - 1, j - 1, g_.diagonal_weight(i, j), diagonal);
          offer(c, up, i - 1, j, -g_.config().gap_a, vertical);
          offer(c, left, i, j - 1, -g_.config().gap_b, horizontal);
        }
        cur.cells.push_back(c);
        if (c.value > 0) {
          any = true;
          if (!visit(i, j, cur.cells.back())) return false;
        } else if (j >= prev.hi()) {
          break;  // nothing further right can be reached
        }
      }
      if (!any) break;
    }
    return true;
  }

  // The cell of vertex (i, j) from the last run (it must have been reached).
  const Cell& at(std::size_t i, std::size_t j) const {
    const Row& r = rows_[i - si_];
    return r.cells[j - r.lo];
  }
  std::size_t seed_row() const { return si_; }
  std::size_t seed_col() const { return sj_; }

 private:
  Row& next_row() {
    if (used_ == rows_.size()) rows_.emplace_back();
    Row& r = rows_[used_++];
    r.cells.clear();
    return r;
  }

  bool alive(const Cell* tail, std::size_t ti, std::size_t tj) const {
    return tail != nullptr && (tail->value > 0 || (ti == si_ && tj == sj_));
  }

  // A step from tail (ti, tj) of weight w: taken if strictly better, so ties keep the earlier step kind.
  void offer(Cell& c, const Cell* tail, std::size_t ti, std::size_t tj, Score w, Step step) const {
    if (!alive(tail, ti, tj)) return;
    const Score v = g_.clamp(tail->value + w);
    if (v > c.value) c = {v, std::max(v, tail->path_max), step};
  }

  const Grid& g_;
  std::vector<Row> rows_;
  std::size_t used_ = 0;
  std::size_t si_ = 0, sj_ = 0;
};

class LocallyOptimalPass {
 public:
  LocallyOptimalPass(const ScoreSource& scores, const AlignConfig& config)
      : g_(scores, config), zero_(zero_cells(g_)), fill_(g_), check_(g_) {}

  std::vector<LocalAlignment> run() {
    const AlignConfig& c = g_.config();
    const Score floor = std::max(c.threshold, std::numeric_limits<Score>::min());
    const std::size_t m = g_.rows(), n = g_.cols();
    std::vector<LocalAlignment> out;
    for (std::size_t i0 = 0; i0 < m; ++i0) {
      for (std::size_t j0 = 0; j0 < n; ++j0) {
        if (!zero_[i0 * (n + 1) + j0] || !g_.enterable(i0 + 1, j0 + 1)) continue;
        if (!(g_.diagonal_weight(i0 + 1, j0 + 1) > 0)) continue;  // admissible paths start with a positive step
        fill_.run(i0, j0, 0.0F, [&](std::size_t i, std::size_t j, const Fill::Cell& cell) {
          if (cell.value >= floor && cell.path_max <= cell.value && !extendable(i, j, cell.value)) {
            out.push_back(trace(i, j, cell.value));
          }
          return true;
        });
      }
    }
    std::sort(out.begin(), out.end(), best_first);  // one pass: one direction
    if (out.size() > c.max_alignments) out.resize(c.max_alignments);
    return out;
  }

 private:
  // Does a non-empty path from (i, j), started at score s, stay positive and return to s or above?
  bool extendable(std::size_t i, std::size_t j, Score s) {
    const AlignConfig& c = g_.config();
    // The common cases without a fill: a step that does not lose.
    if (g_.enterable(i + 1, j + 1) && g_.clamp(s + g_.diagonal_weight(i + 1, j + 1)) >= s) return true;
    if (c.gap_a == 0 && g_.enterable(i + 1, j)) return true;
    if (c.gap_b == 0 && g_.enterable(i, j + 1)) return true;
    return !check_.run(i, j, s, [s](std::size_t, std::size_t, const Fill::Cell& cell) { return cell.value < s; });
  }

  LocalAlignment trace(std::size_t i, std::size_t j, Score score) const {
    LocalAlignment a;
    a.score = score;
    a.direction = g_.config().direction;
    while (i != fill_.seed_row() || j != fill_.seed_col()) {
      switch (fill_.at(i, j).step) {
        case diagonal:
          a.pairs.emplace_back(i - 1, g_.original_col(j));
          --i;
          --j;
          break;
        case vertical:
          --i;
          break;
        case horizontal:
          --j;
          break;
        case none:
          throw std::logic_error("locally optimal traceback left its fill");
      }
    }
    std::reverse(a.pairs.begin(), a.pairs.end());
    a.a_begin = a.pairs.front().first;
    a.a_end = a.pairs.back().first + 1;
    const auto [b_lo, b_hi] = std::minmax(a.pairs.front().second, a.pairs.back().second);
    a.b_begin = b_lo;
    a.b_end = b_hi + 1;
    return a;
  }

  Grid g_;
  std::vector<std::uint8_t> zero_;
  Fill fill_;
  Fill check_;
};

}  // namespace

std::vector<LocalAlignment> locally_optimal_alignments(const ScoreSource& scores, const AlignConfig& config) {
  detail::check_config(scores.rows(), scores.cols(), config);
  if (scores.rows() == 0 || scores.cols() == 0 || config.max_alignments == 0) return {};
  return LocallyOptimalPass(scores, config).run();
}

std::vector<LocalAlignment> locally_optimal_alignments_both(const ScoreSource& scores, AlignConfig config,
                                                            unsigned threads) {
  return both_directions(&locally_optimal_alignments, scores, config, threads);
}

}  // namespace seqtopo::align
