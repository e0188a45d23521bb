#include "seqtopo/align/smith_waterman.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <future>
#include <stdexcept>
#include <string>

#include "check_config.hpp"
#include "plateau.hpp"
#include "search_region.hpp"
#include "seqtopo/align/capped_cell.hpp"
#include "step_box.hpp"

namespace seqtopo::align {

std::string_view to_string(Direction direction) { return direction == Direction::forward ? "forward" : "reverse"; }

namespace {

constexpr Score kNegInf = -std::numeric_limits<Score>::infinity();

// The dynamic-programming table of one pass. Cells use 1-based (i, j); column j of the pass is column
// j-1 of B, or column n-j of B for the reverse pass. Cells outside the searched region stay 0.
class Pass {
  using Cell = std::pair<std::size_t, std::size_t>;  // (i, j) in pass coordinates

 public:
  Pass(const ScoreSource& scores, const AlignConfig& config)
      : scores_(scores),
        config_(config),
        m_(scores.rows()),
        n_(scores.cols()),
        stride_(n_ + 1),
        h_((m_ + 1) * stride_, 0.0F),
        row_best_(m_ + 1, {0.0F, 0}),
        buffer_(n_) {
    for (std::size_t i = 1; i <= m_; ++i) {
      auto [lo, hi] = region(i);
      if (lo <= hi) compute_cells(i, lo, hi);
      rescan_row_best(i);
    }
  }

  std::vector<LocalAlignment> run() {
    std::vector<LocalAlignment> out;
    const Score floor = std::max(config_.threshold, std::numeric_limits<Score>::min());
    while (out.size() < config_.max_alignments) {
      const Cell first = best_cell();
      if (first.first == 0 || h(first.first, first.second) < floor) break;
      // A maximum at the cap is a plateau: take it whole. Otherwise the first maximum, as SIM does.
      const Cell end = config_.cap && h(first.first, first.second) == *config_.cap ? far_end(first) : first;
      out.push_back(recover(end));
      forbid_and_update(out.back());
    }
    return out;
  }

 private:
  // Columns [lo, hi] (1-based, inclusive) that row i may use (lo > hi: none).
  std::pair<std::size_t, std::size_t> region(std::size_t i) const { return detail::search_region(config_, n_, i); }

  bool in_region(std::size_t i, std::size_t j) const {
    auto [lo, hi] = region(i);
    return j >= lo && j <= hi;
  }

  Score& h(std::size_t i, std::size_t j) { return h_[i * stride_ + j]; }
  Score h(std::size_t i, std::size_t j) const { return h_[i * stride_ + j]; }

  std::size_t original_col(std::size_t j) const { return config_.direction == Direction::forward ? j - 1 : n_ - j; }

  // Scores of pass row i, pass columns [lo, hi] into buffer_[lo-1 .. hi-1].
  void fetch(std::size_t i, std::size_t lo, std::size_t hi) {
    if (config_.direction == Direction::forward) {
      scores_.read_row(i - 1, lo - 1, hi, buffer_.data() + (lo - 1));
    } else {
      // pass columns lo..hi are original columns n-hi .. n-lo, in the opposite order
      scores_.read_row(i - 1, n_ - hi, n_ - lo + 1, buffer_.data() + (lo - 1));
      std::reverse(buffer_.begin() + static_cast<std::ptrdiff_t>(lo - 1),
                   buffer_.begin() + static_cast<std::ptrdiff_t>(hi));
    }
  }

  bool used(std::size_t i, std::size_t j) const { return !used_.empty() && used_[(i - 1) * n_ + (j - 1)] != 0; }

  Score clamp(Score v) const { return capped(v, config_.cap); }

  // A diagonal step into a used pair is forbidden (declumping): its step counts as 0, which max(0, ...) ignores.
  Score cell_value(std::size_t i, std::size_t j, Score s) const {
    return capped_cell(used(i, j) ? 0.0F : h(i - 1, j - 1) + s, h(i - 1, j), h(i, j - 1), config_.gap_a, config_.gap_b,
                       config_.cap);
  }

  void compute_cells(std::size_t i, std::size_t lo, std::size_t hi) {
    fetch(i, lo, hi);
    for (std::size_t j = lo; j <= hi; ++j) h(i, j) = cell_value(i, j, buffer_[j - 1]);
  }

  void rescan_row_best(std::size_t i) {
    std::pair<Score, std::size_t> best{0.0F, 0};
    for (std::size_t j = 1; j <= n_; ++j) {
      if (h(i, j) > best.first) best = {h(i, j), j};  // the first maximum of the row
    }
    row_best_[i] = best;
  }

  // The first maximal cell in row-major order ({0, 0} if none is positive).
  Cell best_cell() const {
    std::size_t bi = 0;
    for (std::size_t i = 1; i <= m_; ++i) {
      if (row_best_[i].second != 0 && (bi == 0 || row_best_[i].first > row_best_[bi].first)) bi = i;
    }
    return {bi, bi == 0 ? 0 : row_best_[bi].second};
  }

  Score h(Cell c) const { return h(c.first, c.second); }
  Score score_at(std::size_t i, std::size_t j) const { return scores_.at(i - 1, original_col(j)); }

  // "Tight" steps into cell (i, j): steps that attain the cell's (positive) value, i.e. steps of an
  // optimal alignment ending there. The same expressions as in cell_value, so equality is exact.
  bool tight_diag(std::size_t i, std::size_t j) const {
    return h(i, j) > 0 && !used(i, j) && clamp(h(i - 1, j - 1) + score_at(i, j)) == h(i, j);
  }
  bool tight_down(std::size_t i, std::size_t j) const {  // from (i-1, j): element of A against a gap
    return h(i, j) > 0 && clamp(h(i - 1, j) - config_.gap_a) == h(i, j);
  }
  bool tight_right(std::size_t i, std::size_t j) const {  // from (i, j-1): element of B against a gap
    return h(i, j) > 0 && clamp(h(i, j - 1) - config_.gap_b) == h(i, j);
  }

  // The last maximal cell (row-major) reachable from `first` by tight steps: for a maximum at the cap,
  // the far end of its plateau.
  Cell far_end(Cell first) const {
    struct Grid {
      const Pass& p;
      Score top_value;
      bool top(std::size_t i, std::size_t j) const { return p.h(i, j) == top_value; }
      bool right(std::size_t i, std::size_t j) const { return p.tight_right(i, j); }
      void next_row() const {}
      bool down(std::size_t i, std::size_t j) const { return p.tight_down(i, j); }
      bool diag(std::size_t i, std::size_t j) const { return p.tight_diag(i, j); }
    };
    return detail::plateau_far_end(first, m_, n_, Grid{*this, h(first)});
  }

  // The latest start (largest i, then largest j) of an optimal alignment ending at `end`: the zero cell
  // just before its first pair. Searched backwards along tight steps, one row at a time; `spans`
  // receives, from the end's row upwards, the column span of the cells that reach the end.
  Cell start_of(Cell end, std::vector<std::pair<std::size_t, std::size_t>>& spans) const {
    spans.clear();
    std::vector<std::size_t> seeds{end.second}, closed;
    for (std::size_t i = end.first; i > 0; --i) {
      std::sort(seeds.begin(), seeds.end(), std::greater<>());
      seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
      closed.clear();
      for (std::size_t j : seeds) {  // close the row under leftward tight steps
        if (!closed.empty() && j >= closed.back()) continue;
        closed.push_back(j);
        while (j > 1 && tight_right(i, j)) closed.push_back(--j);
      }
      spans.emplace_back(closed.back(), closed.front());
      seeds.clear();
      std::size_t start_col = 0;
      bool found = false;
      for (std::size_t j : closed) {
        if (tight_diag(i, j)) {
          if (h(i - 1, j - 1) == 0) {
            if (!found || j - 1 > start_col) start_col = j - 1;
            found = true;
          } else {
            seeds.push_back(j - 1);
          }
        }
        if (tight_down(i, j)) seeds.push_back(j);
      }
      if (found) return {i - 1, start_col};
    }
    throw std::logic_error("alignment has no start");
  }

  // Tight steps between the start and the end, so the bisection below reads no scores. Only cells of
  // an optimal start-to-end path matter, and all of those reach the end: row r keeps just the columns
  // lo[r] .. hi[r] that start_of found reaching it (relative to the start; everything else reads 0).
  // Step bits: 1 diagonal step into the cell, 2 step down into it, 4 step right into it.
  LocalAlignment recover(Cell end) {
    std::vector<std::pair<std::size_t, std::size_t>> spans;
    const Cell start = start_of(end, spans);
    detail::StepBox box;
    box.layout(start, spans, end.first - start.first + 1);
    const std::size_t rows = box.lo.size();
    for (std::size_t r = 1; r < rows; ++r) {
      const std::size_t i = box.r0 + r;
      fetch(i, box.c0 + box.lo[r], box.c0 + box.hi[r]);
      for (std::size_t c = box.lo[r]; c <= box.hi[r]; ++c) {
        const std::size_t j = box.c0 + c;
        const Score v = h(i, j);
        if (v <= 0) continue;
        std::uint8_t bits = 0;
        if (!used(i, j) && clamp(h(i - 1, j - 1) + buffer_[j - 1]) == v) bits |= 1U;
        if (clamp(h(i - 1, j) - config_.gap_a) == v) bits |= 2U;
        if (clamp(h(i, j - 1) - config_.gap_b) == v) bits |= 4U;
        box.steps[box.index(r, c)] = bits;
      }
    }
    return detail::alignment_through(box, end, config_.direction, n_, h(end));
  }

  // Forbids the alignment's pairs and recomputes, row by row, only the cells whose value can change:
  // a cell changes only if it was just forbidden or one of its three predecessors changed.
  void forbid_and_update(const LocalAlignment& a) {
    if (used_.empty()) used_.assign(m_ * n_, 0);
    std::vector<std::vector<std::size_t>> seeds_by_row;  // pass columns newly forbidden, per row offset
    const std::size_t first_row = a.pairs.front().first + 1;
    const std::size_t last_row = a.pairs.back().first + 1;
    seeds_by_row.resize(last_row - first_row + 1);
    for (auto [r, c] : a.pairs) {
      const std::size_t j = config_.direction == Direction::forward ? c + 1 : n_ - c;
      used_[r * n_ + (j - 1)] = 1;
      seeds_by_row[r + 1 - first_row].push_back(j);
    }

    std::vector<std::size_t> changed_prev, changed_cur, candidates;
    for (std::size_t i = first_row; i <= m_; ++i) {
      candidates.clear();
      for (std::size_t j : changed_prev) {
        candidates.push_back(j);
        if (j < n_) candidates.push_back(j + 1);
      }
      // The changed columns come in increasing order, so these candidates are already sorted: only the row's few
      // seeds are sorted and merged in (a whole sort per row was a few percent of a localization).
      const auto from_changes = static_cast<std::ptrdiff_t>(candidates.size());
      if (i <= last_row) {
        const auto& seeds = seeds_by_row[i - first_row];
        candidates.insert(candidates.end(), seeds.begin(), seeds.end());
      }
      if (candidates.empty()) {
        if (i >= last_row) break;
        changed_prev.clear();
        continue;
      }
      std::sort(candidates.begin() + from_changes, candidates.end());
      std::inplace_merge(candidates.begin(), candidates.begin() + from_changes, candidates.end());
      candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());

      changed_cur.clear();
      auto [lo, hi] = region(i);
      bool best_changed = false;
      std::size_t next = 0;       // index into candidates
      std::size_t left_next = 0;  // column to visit because its left neighbour changed (0 = none)
      while (next < candidates.size() || left_next != 0) {
        std::size_t j;
        if (left_next != 0 && (next >= candidates.size() || left_next <= candidates[next])) {
          j = left_next;
          if (next < candidates.size() && candidates[next] == j) ++next;
        } else {
          j = candidates[next++];
        }
        left_next = 0;
        if (j < lo || j > hi) continue;
        const Score s = scores_.at(i - 1, original_col(j));
        const Score v = cell_value(i, j, s);
        if (v != h(i, j)) {
          h(i, j) = v;
          changed_cur.push_back(j);
          if (j == row_best_[i].second) best_changed = true;
          if (j < hi) left_next = j + 1;
        }
      }
      // Values only decrease, so the row's best moves only if the best cell itself changed.
      if (best_changed) rescan_row_best(i);
      if (changed_cur.empty() && i >= last_row) break;
      std::swap(changed_prev, changed_cur);
    }
  }

  const ScoreSource& scores_;
  const AlignConfig& config_;
  std::size_t m_, n_, stride_;
  std::vector<Score> h_;
  std::vector<std::uint8_t> used_;
  std::vector<std::pair<Score, std::size_t>> row_best_;  // (value, column) of each row's best cell; column 0 = none
  std::vector<Score> buffer_;
};

}  // namespace

std::vector<LocalAlignment> local_alignments(const ScoreSource& scores, const AlignConfig& config) {
  detail::check_config(scores.rows(), scores.cols(), config);
  if (scores.rows() == 0 || scores.cols() == 0 || config.max_alignments == 0) return {};
  return Pass(scores, config).run();
}

bool best_first(const LocalAlignment& x, const LocalAlignment& y) {
  if (x.score != y.score) return x.score > y.score;
  if (x.direction != y.direction) return x.direction == Direction::forward;
  if (x.a_begin != y.a_begin) return x.a_begin < y.a_begin;
  if (x.b_begin != y.b_begin) return x.b_begin < y.b_begin;
  // Only alignments that may share pairs (the locally optimal set) get this far.
  if (x.a_end != y.a_end) return x.a_end < y.a_end;
  if (x.b_end != y.b_end) return x.b_end < y.b_end;
  return x.pairs < y.pairs;
}

std::vector<LocalAlignment> merge_directions(std::vector<LocalAlignment> forward, std::vector<LocalAlignment> reverse,
                                             std::size_t max_alignments) {
  std::vector<LocalAlignment> all = std::move(forward);
  all.reserve(all.size() + reverse.size());
  std::move(reverse.begin(), reverse.end(), std::back_inserter(all));
  std::stable_sort(all.begin(), all.end(), best_first);
  if (all.size() > max_alignments) all.resize(max_alignments);
  return all;
}

std::vector<LocalAlignment> both_directions(AlignmentPass pass, const ScoreSource& scores, AlignConfig config,
                                            unsigned threads) {
  AlignConfig forward = config, reverse = config;
  forward.direction = Direction::forward;
  reverse.direction = Direction::reverse;
  std::vector<LocalAlignment> fwd, rev;
  if (threads > 1) {
    auto rev_future = std::async(std::launch::async, [&] { return pass(scores, reverse); });
    fwd = pass(scores, forward);
    rev = rev_future.get();
  } else {
    fwd = pass(scores, forward);
    rev = pass(scores, reverse);
  }
  return merge_directions(std::move(fwd), std::move(rev), config.max_alignments);
}

std::vector<LocalAlignment> local_alignments_both(const ScoreSource& scores, AlignConfig config, unsigned threads) {
  return both_directions(&local_alignments, scores, config, threads);
}

}  // namespace seqtopo::align
