#include "seqtopo/scale/sparse_components.hpp"

#include <algorithm>
#include <future>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "both_passes.hpp"
#include "seqtopo/align/capped_cell.hpp"
#include "seqtopo/align/smith_waterman.hpp"
#include "seqtopo/core/disjoint_sets.hpp"

namespace seqtopo::scale {

using align::AlignConfig;
using align::Direction;
using align::LocalAlignment;

bool SparseComponent::contains(std::size_t row, std::size_t pass_col) const {
  if (row < row_begin || row >= row_end) return false;
  const std::size_t r = row - row_begin;
  const auto first = runs.begin() + static_cast<std::ptrdiff_t>(run_begin[r]);
  const auto last = runs.begin() + static_cast<std::ptrdiff_t>(run_begin[r + 1]);
  auto it =
      std::upper_bound(first, last, pass_col, [](std::size_t v, const SparseRun& run) { return v < run.pass_col; });
  if (it == first) return false;
  --it;
  return pass_col < std::size_t{it->pass_col} + it->length;
}

namespace {

struct Cell {
  std::uint32_t col;  // pass column (0-based)
  float h;
  std::uint32_t label;  // a label of its component (uf_: a set's root is its smallest label, its first cell's)
};

const Cell* find_cell(const std::vector<Cell>& row, std::size_t col) {
  const auto it = std::lower_bound(row.begin(), row.end(), col, [](const Cell& c, std::size_t v) { return c.col < v; });
  return it != row.end() && it->col == col ? &*it : nullptr;
}

// The engine's first fill restricted to the cells where H can be positive, with the components of
// the recurrence (a cell joins the components of its positive predecessors). Holds two rows of cells
// and the working state of the components that still have a cell in the last row: a component without
// one can never grow again (a positive cell's positive predecessors are in its row or the row above),
// so it is closed there, kept if it reaches the threshold and forgotten otherwise.
class SparseFill {
 public:
  SparseFill(const SparseScores& scores, const AlignConfig& config)
      : s_(scores),
        config_(config),
        m_(scores.rows()),
        n_(scores.cols()),
        floor_(std::max(config.threshold, std::numeric_limits<float>::min())) {}

  // The components whose best cell reaches the threshold, in the row-major order of their first cells.
  std::vector<SparseComponent> run(SparseAlignStats& stats) {
    std::vector<Cell> prev, cur;
    std::vector<std::pair<std::uint32_t, float>> cand;
    std::vector<std::uint32_t> seeds, live, still_live;
    const float bg = s_.background();
    for (std::size_t i = 0; i < m_; ++i) {
      std::swap(prev, cur);
      cur.clear();
      const auto [lo, hi] = region(i);
      if (lo <= hi) {
        pass_candidates(i, cand);
        seeds.clear();
        for (const Cell& c : prev) {
          seeds.push_back(c.col);
          if (c.col + 1U < n_) seeds.push_back(c.col + 1U);
        }
        for (const auto& [t, v] : cand) {
          if (v > 0) seeds.push_back(t);
        }
        std::sort(seeds.begin(), seeds.end());
        seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
        std::size_t next = 0;
        constexpr std::size_t none = std::numeric_limits<std::size_t>::max();
        std::size_t left_next = none;
        while (next < seeds.size() || left_next != none) {
          std::size_t t;
          if (left_next != none && (next >= seeds.size() || left_next <= seeds[next])) {
            t = left_next;
            if (next < seeds.size() && seeds[next] == t) ++next;
          } else {
            t = seeds[next++];
          }
          left_next = none;
          if (t < lo || t > hi) continue;
          const auto cit =
              std::lower_bound(cand.begin(), cand.end(), t, [](const auto& c, std::size_t v) { return c.first < v; });
          const float s = cit != cand.end() && cit->first == t ? cit->second : bg;
          const Cell* diag = t > 0 ? find_cell(prev, t - 1) : nullptr;
          const Cell* up = find_cell(prev, t);
          const Cell* left = !cur.empty() && t > 0 && cur.back().col == t - 1 ? &cur.back() : nullptr;
          // The engine's cell, with inactive neighbours at 0.
          const float v =
              align::capped_cell((diag != nullptr ? diag->h : 0.0F) + s, up != nullptr ? up->h : 0.0F,
                                 left != nullptr ? left->h : 0.0F, config_.gap_a, config_.gap_b, config_.cap);
          if (!(v > 0)) continue;
          std::uint32_t label = std::numeric_limits<std::uint32_t>::max();
          for (const Cell* p : {diag, up, left}) {
            if (p != nullptr)
              label = label == std::numeric_limits<std::uint32_t>::max() ? find(p->label) : unite(label, p->label);
          }
          if (label == std::numeric_limits<std::uint32_t>::max()) label = open(i);
          cur.push_back({static_cast<std::uint32_t>(t), v, label});
          ++stats.active_cells;
          if (t < hi) left_next = t + 1;
        }
      }
      // The row's runs of consecutive cells, each all of one component (a cell joins its left neighbour).
      still_live.clear();
      for (std::size_t a = 0; a < cur.size();) {
        std::size_t b = a + 1;
        float best = cur[a].h;
        while (b < cur.size() && cur[b].col == cur[b - 1].col + 1U) best = std::max(best, cur[b++].h);
        Open& o = open_[slot_[uf_.find(cur[a].label)]];
        o.runs.push_back({i, {cur[a].col, static_cast<std::uint32_t>(b - a)}});
        o.col_lo = std::min(o.col_lo, cur[a].col);
        o.col_hi = std::max(o.col_hi, cur[b - 1].col);
        o.best = std::max(o.best, best);
        o.last_row = i;
        if (o.listed != i) {
          o.listed = i;
          still_live.push_back(uf_.find(cur[a].label));
        }
        a = b;
      }
      for (const std::uint32_t root : live) {
        if (uf_.find(root) == root && open_[slot_[root]].last_row < i) close(root, stats);
      }
      std::swap(live, still_live);
    }
    for (const std::uint32_t root : live) close(root, stats);
    std::sort(closed_.begin(), closed_.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    std::vector<SparseComponent> out;
    out.reserve(closed_.size());
    for (auto& [label, c] : closed_) {
      c.order = out.size();
      ++stats.aligned_components;
      stats.box_cells += c.box_cells();
      stats.largest_box_cells = std::max(stats.largest_box_cells, c.box_cells());
      out.push_back(std::move(c));
    }
    return out;
  }

 private:
  struct RowRun {
    std::size_t row;
    SparseRun run;
  };
  // A component still growing, in the slot of its root label.
  struct Open {
    std::size_t first_row = 0, last_row = 0;                       // last_row: the latest row with one of its cells
    std::size_t listed = std::numeric_limits<std::size_t>::max();  // the row whose live list holds it
    std::uint32_t col_lo = std::numeric_limits<std::uint32_t>::max(), col_hi = 0;  // pass columns, inclusive
    float best = 0;
    std::vector<RowRun> runs;  // by row, except after a union (put in order when closed)
  };

  std::uint32_t find(std::uint32_t label) { return uf_.find(label); }

  // A new component whose first cell is in row i.
  std::uint32_t open(std::size_t i) {
    const std::uint32_t label = uf_.add();
    std::uint32_t slot;
    if (free_.empty()) {
      slot = static_cast<std::uint32_t>(open_.size());
      open_.emplace_back();
    } else {
      slot = free_.back();
      free_.pop_back();
    }
    slot_.push_back(slot);
    open_[slot].first_row = i;
    open_[slot].last_row = i;
    return label;
  }

  void release(std::uint32_t slot) {
    open_[slot] = Open{};
    free_.push_back(slot);
  }

  // The union of the component of `root` (a root) and the one of `label`; returns the new root.
  std::uint32_t unite(std::uint32_t root, std::uint32_t label) {
    const std::uint32_t other = uf_.find(label);
    if (other == root) return root;
    const auto [kept, absorbed] = uf_.unite(root, other);
    Open& k = open_[slot_[kept]];
    Open& a = open_[slot_[absorbed]];
    if (k.runs.size() < a.runs.size()) std::swap(k.runs, a.runs);
    k.runs.insert(k.runs.end(), a.runs.begin(), a.runs.end());
    k.first_row = std::min(k.first_row, a.first_row);
    k.last_row = std::max(k.last_row, a.last_row);
    k.col_lo = std::min(k.col_lo, a.col_lo);
    k.col_hi = std::max(k.col_hi, a.col_hi);
    k.best = std::max(k.best, a.best);
    release(slot_[absorbed]);
    return kept;
  }

  // The component of `root` has no cell in the current row: kept if it reaches the threshold.
  void close(std::uint32_t root, SparseAlignStats& stats) {
    ++stats.components;
    Open& o = open_[slot_[root]];
    if (o.best >= floor_) {
      std::sort(o.runs.begin(), o.runs.end(), [](const RowRun& x, const RowRun& y) {
        return x.row != y.row ? x.row < y.row : x.run.pass_col < y.run.pass_col;
      });
      SparseComponent c = component(o.first_row, o.last_row, o.col_lo, o.col_hi, o.best);
      c.run_begin.reserve(c.row_end - c.row_begin + 1);
      c.runs.reserve(o.runs.size());
      for (const RowRun& r : o.runs) {
        while (c.run_begin.size() < r.row - c.row_begin + 1) c.run_begin.push_back(c.runs.size());
        c.runs.push_back(r.run);
      }
      while (c.run_begin.size() < c.row_end - c.row_begin + 1) c.run_begin.push_back(c.runs.size());
      closed_.emplace_back(root, std::move(c));
    }
    release(slot_[root]);
  }

  std::size_t original_col(std::size_t t) const { return config_.direction == Direction::forward ? t : n_ - 1 - t; }

  SparseComponent component(std::size_t i0, std::size_t i1, std::size_t t0, std::size_t t1, float best) const {
    SparseComponent c;
    c.direction = config_.direction;
    c.row_begin = i0;
    c.row_end = i1 + 1;
    c.pass_col_begin = t0;
    c.pass_col_end = t1 + 1;
    c.best = best;
    std::size_t r0 = i0, r1 = i1;
    std::size_t c0 = std::min(original_col(t0), original_col(t1));
    std::size_t c1 = std::max(original_col(t0), original_col(t1));
    // Inside the self band (r - c >= sep for every cell of the box) the band plays no part; otherwise
    // the engine needs the band itself: a square box on the diagonal.
    const bool inside = !config_.self || (r0 >= c1 && r0 - c1 >= config_.min_separation);
    if (!inside) {
      r0 = c0 = std::min(r0, c0);
      r1 = c1 = std::max(r1, c1);
    }
    c.kind = inside ? SparseBoxKind::inside_band : SparseBoxKind::diagonal_square;
    c.box_row_begin = r0;
    c.box_row_end = r1 + 1;
    c.box_col_begin = c0;
    c.box_col_end = c1 + 1;
    return c;
  }

  // Pass columns [lo, hi] (0-based, inclusive) of row i, as the engine's region(); lo > hi if none.
  std::pair<std::size_t, std::size_t> region(std::size_t r) const {
    if (!config_.self) return {0, n_ - 1};
    const std::size_t sep = config_.min_separation;
    if (config_.direction == Direction::forward) {
      if (r < sep) return {1, 0};
      return {0, r - sep};
    }
    const std::size_t t_lo = n_ - 1 - r + sep;
    if (t_lo >= n_) return {1, 0};
    return {t_lo, n_ - 1};
  }

  // Row i's candidates in pass columns, increasing.
  void pass_candidates(std::size_t i, std::vector<std::pair<std::uint32_t, float>>& out) const {
    out.clear();
    const auto cols = s_.row_columns(i);
    const auto vals = s_.row_values(i);
    if (config_.direction == Direction::forward) {
      for (std::size_t k = 0; k < cols.size(); ++k) out.emplace_back(cols[k], vals[k]);
    } else {
      for (std::size_t k = cols.size(); k-- > 0;) {
        out.emplace_back(static_cast<std::uint32_t>(n_ - 1 - cols[k]), vals[k]);
      }
    }
  }

  const SparseScores& s_;
  const AlignConfig& config_;
  std::size_t m_, n_;
  float floor_;
  // Component labels: one per cell without a positive predecessor (the first cell of a component), joined as the
  // recurrence connects them.
  DisjointSets<std::uint32_t> uf_;
  std::vector<std::uint32_t> slot_;  // label -> slot in open_ (meaningful for open roots)
  std::vector<Open> open_;
  std::vector<std::uint32_t> free_;
  std::vector<std::pair<std::uint32_t, SparseComponent>> closed_;  // (root label, component) kept
};

AlignConfig component_config(const AlignConfig& config, const SparseComponent& c) {
  AlignConfig cfg = config;
  cfg.direction = c.direction;
  cfg.max_alignments = std::numeric_limits<std::size_t>::max();
  cfg.self = c.kind == SparseBoxKind::diagonal_square;
  return cfg;
}

// Row-major position (in pass coordinates) of the component's first cell at alignment k's score, just
// before the engine took it: the box is refilled with the component's earlier pairs used.
std::uint64_t first_max_key(const SparseScores& s, const AlignConfig& config, const SparseComponent& g,
                            const std::vector<LocalAlignment>& alignments, std::size_t k) {
  const std::size_t n = s.cols();
  const std::size_t r0 = g.box_row_begin, r1 = g.box_row_end - 1, c0 = g.box_col_begin, c1 = g.box_col_end - 1;
  const std::size_t cols = c1 - c0 + 1;
  const bool self = g.kind == SparseBoxKind::diagonal_square;
  std::vector<std::uint8_t> used((r1 - r0 + 1) * cols, 0);
  const bool fwd = g.direction == Direction::forward;
  auto box_col = [&](std::size_t c) { return fwd ? c - c0 : c1 - c; };  // box pass column of original c
  for (std::size_t e = 0; e < k; ++e) {
    for (const auto& [pi, pj] : alignments[e].pairs) used[(pi - r0) * cols + box_col(pj)] = 1;
  }
  const float target = alignments[k].score;
  std::vector<float> prev(cols + 1, 0.0F), cur(cols + 1, 0.0F);
  for (std::size_t r = r0; r <= r1; ++r) {
    cur[0] = 0.0F;
    for (std::size_t tb = 0; tb < cols; ++tb) {
      const std::size_t c = fwd ? c0 + tb : c1 - tb;
      float v = 0.0F;
      if (!self || (r >= c && r - c >= config.min_separation)) {
        const float step = used[(r - r0) * cols + tb] == 0 ? prev[tb] + s.at(r, c) : 0.0F;  // 0: forbidden
        v = align::capped_cell(step, prev[tb + 1], cur[tb], config.gap_a, config.gap_b, config.cap);
      }
      cur[tb + 1] = v;
      if (v == target) {
        const std::size_t t = fwd ? c : n - 1 - c;
        if (g.contains(r, t)) return static_cast<std::uint64_t>(r) * n + t;
      }
    }
    std::swap(prev, cur);
  }
  return std::numeric_limits<std::uint64_t>::max();
}

void check(const SparseScores& scores, const AlignConfig& config) {
  // The engine's own checks first (same messages), on an empty matrix of the same shape.
  AlignConfig c = config;
  c.max_alignments = 0;
  align::local_alignments(
      align::ScoreSource(scores.rows(), scores.cols(), [](std::size_t, std::size_t, std::size_t, float*) {}), c);
  if (!(scores.background() < 0)) throw std::invalid_argument("sparse alignment needs a background score < 0");
  if (!(config.gap_a > 0) || !(config.gap_b > 0))
    throw std::invalid_argument("sparse alignment needs gap penalties > 0");
}

void check_aligned(std::span<const SparseComponent> components,
                   const std::vector<std::vector<LocalAlignment>>& aligned) {
  if (aligned.size() != components.size()) {
    throw std::invalid_argument("merge of component alignments: one list of alignments per component needed");
  }
}

}  // namespace

std::vector<SparseComponent> sparse_components(const SparseScores& scores, const AlignConfig& config,
                                               SparseAlignStats* stats) {
  check(scores, config);
  SparseAlignStats local;
  std::vector<SparseComponent> out;
  if (scores.rows() > 0 && scores.cols() > 0 && config.max_alignments > 0) {
    SparseFill fill(scores, config);
    out = fill.run(local);
  }
  if (stats != nullptr) *stats = local;
  return out;
}

std::vector<SparseComponent> sparse_components_both(const SparseScores& scores, const AlignConfig& config,
                                                    unsigned threads, SparseAlignStats* stats) {
  auto [fwd, rev] = detail::both_passes(config, threads, stats, [&](const AlignConfig& c, SparseAlignStats* st) {
    return sparse_components(scores, c, st);
  });
  fwd.insert(fwd.end(), std::make_move_iterator(rev.begin()), std::make_move_iterator(rev.end()));
  return fwd;
}

std::vector<LocalAlignment> align_component(const SparseScores& scores, const AlignConfig& config,
                                            const SparseComponent& component) {
  const std::size_t n = scores.cols();
  const std::size_t r0 = component.box_row_begin, c0 = component.box_col_begin;
  const std::size_t rows = component.box_row_end - r0, cols = component.box_col_end - c0;
  if (component.box_row_end > scores.rows() || component.box_col_end > n || rows == 0 || cols == 0) {
    throw std::invalid_argument("align_component: the component's box is outside the score matrix");
  }
  const align::ScoreSource sub(rows, cols, [&scores, r0, c0](std::size_t i, std::size_t jb, std::size_t je, float* o) {
    scores.read_row(r0 + i, c0 + jb, c0 + je, o);
  });
  std::vector<LocalAlignment> out;
  for (LocalAlignment& a : align::local_alignments(sub, component_config(config, component))) {
    // Other components inside the box are aligned by their own box.
    const std::size_t gi = a.pairs.front().first + r0, gc = a.pairs.front().second + c0;
    const std::size_t t = component.direction == Direction::forward ? gc : n - 1 - gc;
    if (!component.contains(gi, t)) continue;
    a.a_begin += r0;
    a.a_end += r0;
    a.b_begin += c0;
    a.b_end += c0;
    for (auto& [pi, pj] : a.pairs) {
      pi += r0;
      pj += c0;
    }
    out.push_back(std::move(a));
  }
  return out;
}

namespace {

// One pass's merge; components[k] is aligned[k]'s component.
std::vector<LocalAlignment> merge_pass(const SparseScores& scores, const AlignConfig& config,
                                       const std::vector<const SparseComponent*>& components,
                                       std::vector<std::vector<LocalAlignment>> aligned) {
  for (const SparseComponent* c : components) {
    if (c->direction != config.direction) {
      throw std::invalid_argument("merge of component alignments: a component of the other direction");
    }
  }
  // The base order is the components' own (first cell, row-major) and, within one, the engine's: the
  // stable sorts below then give the same order whatever order the components came in.
  std::vector<std::size_t> by_order(components.size());
  std::iota(by_order.begin(), by_order.end(), std::size_t{0});
  std::sort(by_order.begin(), by_order.end(),
            [&](std::size_t x, std::size_t y) { return components[x]->order < components[y]->order; });
  struct Ref {
    std::size_t group, index;
    std::uint64_t first_max;
  };
  std::vector<Ref> order;
  for (const std::size_t g : by_order) {
    for (std::size_t k = 0; k < aligned[g].size(); ++k) order.push_back({g, k, 0});
  }
  auto at = [&](const Ref& r) -> const LocalAlignment& { return aligned[r.group][r.index]; };
  auto key_less = [&](const Ref& x, const Ref& y) {
    const LocalAlignment& a = at(x);
    const LocalAlignment& b = at(y);
    if (a.score != b.score) return a.score > b.score;
    if (a.a_begin != b.a_begin) return a.a_begin < b.a_begin;
    return a.b_begin < b.b_begin;
  };
  std::stable_sort(order.begin(), order.end(), key_less);
  // Equal keys from different components (possible in the reverse pass, where b_begin is the last
  // pair's column) are put in the dense engine's order: by the row-major position of the first
  // maximal cell when each was taken.
  for (std::size_t lo = 0; lo < order.size();) {
    std::size_t hi = lo + 1;
    while (hi < order.size() && !key_less(order[lo], order[hi])) ++hi;
    if (hi - lo > 1) {
      for (std::size_t k = lo; k < hi; ++k) {
        order[k].first_max =
            first_max_key(scores, config, *components[order[k].group], aligned[order[k].group], order[k].index);
      }
      std::stable_sort(order.begin() + static_cast<std::ptrdiff_t>(lo), order.begin() + static_cast<std::ptrdiff_t>(hi),
                       [](const Ref& x, const Ref& y) { return x.first_max < y.first_max; });
    }
    lo = hi;
  }
  std::vector<LocalAlignment> out;
  out.reserve(std::min(order.size(), config.max_alignments));
  for (const Ref& r : order) {
    if (out.size() >= config.max_alignments) break;
    out.push_back(std::move(aligned[r.group][r.index]));
  }
  return out;
}

}  // namespace

std::vector<LocalAlignment> merge_component_alignments(const SparseScores& scores, const AlignConfig& config,
                                                       std::span<const SparseComponent> components,
                                                       std::vector<std::vector<LocalAlignment>> aligned) {
  check_aligned(components, aligned);
  std::vector<const SparseComponent*> pointers;
  for (const SparseComponent& c : components) pointers.push_back(&c);
  return merge_pass(scores, config, pointers, std::move(aligned));
}

std::vector<LocalAlignment> merge_component_alignments_both(const SparseScores& scores, const AlignConfig& config,
                                                            std::span<const SparseComponent> components,
                                                            std::vector<std::vector<LocalAlignment>> aligned) {
  check_aligned(components, aligned);
  std::vector<LocalAlignment> passes[2];
  for (const Direction d : {Direction::forward, Direction::reverse}) {
    std::vector<const SparseComponent*> mine;
    std::vector<std::vector<LocalAlignment>> mine_aligned;
    for (std::size_t k = 0; k < components.size(); ++k) {
      if (components[k].direction != d) continue;
      mine.push_back(&components[k]);
      mine_aligned.push_back(std::move(aligned[k]));
    }
    AlignConfig pass = config;
    pass.direction = d;
    passes[d == Direction::forward ? 0 : 1] = merge_pass(scores, pass, mine, std::move(mine_aligned));
  }
  return align::merge_directions(std::move(passes[0]), std::move(passes[1]), config.max_alignments);
}

std::vector<std::size_t> deal_components(std::span<const SparseComponent> components, std::size_t ranks) {
  if (ranks == 0) throw std::invalid_argument("deal_components: needs at least one rank");
  std::vector<std::size_t> by_size(components.size());
  std::iota(by_size.begin(), by_size.end(), std::size_t{0});
  std::stable_sort(by_size.begin(), by_size.end(),
                   [&](std::size_t x, std::size_t y) { return components[x].box_cells() > components[y].box_cells(); });
  std::vector<std::uint64_t> load(ranks, 0);
  std::vector<std::size_t> owner(components.size(), 0);
  for (const std::size_t k : by_size) {
    const auto least = static_cast<std::size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    owner[k] = least;
    load[least] += components[k].box_cells();
  }
  return owner;
}

}  // namespace seqtopo::scale
