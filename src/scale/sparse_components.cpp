#include "seqtopo/scale/sparse_components.hpp"

#include <algorithm>
#include <future>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "both_passes.hpp"
#include "seqtopo/align/smith_waterman.hpp"

namespace seqtopo::scale {

using align::AlignConfig;
using align::Direction;
using align::LocalAlignment;

bool SparseComponent::contains(std::size_t row, std::size_t pass_col) const {
  if (row < row_begin || row >= row_end) return false;
  const std::size_t r = row - row_begin;
  const auto first = cells.begin() + static_cast<std::ptrdiff_t>(cell_begin[r]);
  const auto last = cells.begin() + static_cast<std::ptrdiff_t>(cell_begin[r + 1]);
  return std::binary_search(first, last, pass_col,
                            [](auto a, auto b) { return static_cast<std::size_t>(a) < static_cast<std::size_t>(b); });
}

namespace {

struct Cell {
  std::uint32_t col;  // pass column (0-based)
  float h;
  std::uint32_t id;
};

class UnionFind {
 public:
  std::uint32_t add() {
    parent_.push_back(static_cast<std::uint32_t>(parent_.size()));
    return parent_.back();
  }
  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }
  std::size_t size() const { return parent_.size(); }

 private:
  std::vector<std::uint32_t> parent_;
};

const Cell* find_cell(const std::vector<Cell>& row, std::size_t col) {
  const auto it = std::lower_bound(row.begin(), row.end(), col, [](const Cell& c, std::size_t v) { return c.col < v; });
  return it != row.end() && it->col == col ? &*it : nullptr;
}

// The engine's first fill restricted to the cells where H can be positive, with the components of
// the recurrence (a cell joins the components of its positive predecessors).
class SparseFill {
 public:
  SparseFill(const SparseScores& scores, const AlignConfig& config)
      : s_(scores), config_(config), m_(scores.rows()), n_(scores.cols()) {}

  void run() {
    rows_.assign(m_, {});
    std::vector<std::pair<std::uint32_t, float>> cand;
    std::vector<std::uint32_t> seeds;
    const float bg = s_.background();
    for (std::size_t i = 0; i < m_; ++i) {
      const auto [lo, hi] = region(i);
      if (lo > hi) continue;
      pass_candidates(i, cand);
      seeds.clear();
      if (i > 0) {
        for (const Cell& c : rows_[i - 1]) {
          seeds.push_back(c.col);
          if (c.col + 1U < n_) seeds.push_back(c.col + 1U);
        }
      }
      for (const auto& [t, v] : cand) {
        if (v > 0) seeds.push_back(t);
      }
      std::sort(seeds.begin(), seeds.end());
      seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
      std::vector<Cell>& cur = rows_[i];
      const std::vector<Cell>* prev = i > 0 ? &rows_[i - 1] : nullptr;
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
        const Cell* diag = prev != nullptr && t > 0 ? find_cell(*prev, t - 1) : nullptr;
        const Cell* up = prev != nullptr ? find_cell(*prev, t) : nullptr;
        const Cell* left = !cur.empty() && t > 0 && cur.back().col == t - 1 ? &cur.back() : nullptr;
        // The engine's cell_value, with inactive neighbours at 0.
        float v = 0.0F;
        v = std::max(v, (diag != nullptr ? diag->h : 0.0F) + s);
        v = std::max(v, (up != nullptr ? up->h : 0.0F) - config_.gap_a);
        v = std::max(v, (left != nullptr ? left->h : 0.0F) - config_.gap_b);
        if (config_.cap) v = std::min(v, *config_.cap);
        if (!(v > 0)) continue;
        const std::uint32_t id = uf_.add();
        if (diag != nullptr) uf_.unite(id, diag->id);
        if (up != nullptr) uf_.unite(id, up->id);
        if (left != nullptr) uf_.unite(id, left->id);
        cur.push_back({static_cast<std::uint32_t>(t), v, id});
        ++active_;
        if (t < hi) left_next = t + 1;
      }
    }
  }

  // The components whose best cell reaches the threshold, in the row-major order of their first cells.
  std::vector<SparseComponent> components(SparseAlignStats& stats) {
    stats.active_cells += active_;
    constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
    struct Box {
      std::size_t i0 = std::numeric_limits<std::size_t>::max(), i1 = 0;  // pass rows, inclusive
      std::size_t t0 = std::numeric_limits<std::size_t>::max(), t1 = 0;  // pass columns, inclusive
      float best = 0;
    };
    // Bounding box and best value of every component; boxes are numbered by first cell.
    std::vector<std::uint32_t> box_of(uf_.size(), none);
    std::vector<Box> boxes;
    for (std::size_t i = 0; i < m_; ++i) {
      for (const Cell& c : rows_[i]) {
        const std::uint32_t root = uf_.find(c.id);
        if (box_of[root] == none) {
          box_of[root] = static_cast<std::uint32_t>(boxes.size());
          boxes.emplace_back();
        }
        Box& b = boxes[box_of[root]];
        b.i0 = std::min(b.i0, i);
        b.i1 = std::max(b.i1, i);
        b.t0 = std::min<std::size_t>(b.t0, c.col);
        b.t1 = std::max<std::size_t>(b.t1, c.col);
        b.best = std::max(b.best, c.h);
      }
    }
    stats.components += boxes.size();
    const float floor = std::max(config_.threshold, std::numeric_limits<float>::min());
    std::vector<std::uint32_t> out_of(boxes.size(), none);
    std::vector<SparseComponent> out;
    for (std::size_t b = 0; b < boxes.size(); ++b) {
      if (boxes[b].best < floor) continue;
      out_of[b] = static_cast<std::uint32_t>(out.size());
      out.push_back(component(boxes[b].i0, boxes[b].i1, boxes[b].t0, boxes[b].t1, boxes[b].best, out.size()));
      const SparseComponent& c = out.back();
      ++stats.aligned_components;
      stats.box_cells += c.box_cells();
      stats.largest_box_cells = std::max(stats.largest_box_cells, c.box_cells());
    }
    // The cells, visited row by row and by increasing column within a row.
    for (std::size_t i = 0; i < m_; ++i) {
      for (const Cell& c : rows_[i]) {
        const std::uint32_t k = out_of[box_of[uf_.find(c.id)]];
        if (k == none) continue;
        SparseComponent& comp = out[k];
        const std::size_t r = i - comp.row_begin;
        while (comp.cell_begin.size() < r + 1) comp.cell_begin.push_back(comp.cells.size());
        comp.cells.push_back(c.col);
      }
    }
    for (SparseComponent& comp : out) {
      while (comp.cell_begin.size() < comp.row_end - comp.row_begin + 1) comp.cell_begin.push_back(comp.cells.size());
    }
    return out;
  }

 private:
  std::size_t original_col(std::size_t t) const { return config_.direction == Direction::forward ? t : n_ - 1 - t; }

  SparseComponent component(std::size_t i0, std::size_t i1, std::size_t t0, std::size_t t1, float best,
                            std::size_t order) const {
    SparseComponent c;
    c.direction = config_.direction;
    c.order = order;
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
  std::vector<std::vector<Cell>> rows_;
  UnionFind uf_;
  std::size_t active_ = 0;
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
        if (used[(r - r0) * cols + tb] == 0) v = std::max(v, prev[tb] + s.at(r, c));
        v = std::max(v, prev[tb + 1] - config.gap_a);
        v = std::max(v, cur[tb] - config.gap_b);
        if (config.cap) v = std::min(v, *config.cap);
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
    fill.run();
    out = fill.components(local);
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
