#include "seqtopo/scale/sparse_alignment.hpp"

#include <algorithm>
#include <cmath>
#include <future>
#include <limits>
#include <stdexcept>
#include <string>

#include "seqtopo/align/smith_waterman.hpp"

namespace seqtopo::scale {

using align::AlignConfig;
using align::Direction;
using align::LocalAlignment;

SparseScores::SparseScores(std::size_t rows, std::size_t cols, float background, std::vector<SparseEntry> entries)
    : rows_(rows), cols_(cols), background_(background) {
  if (!std::isfinite(background)) throw std::invalid_argument("sparse scores: background must be finite");
  if (cols > std::numeric_limits<std::uint32_t>::max()) throw std::invalid_argument("sparse scores: too many columns");
  std::sort(entries.begin(), entries.end(),
            [](const SparseEntry& a, const SparseEntry& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; });
  row_begin_.assign(rows + 1, 0);
  columns_.reserve(entries.size());
  values_.reserve(entries.size());
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const SparseEntry& e = entries[k];
    if (e.i >= rows || e.j >= cols) {
      throw std::invalid_argument("sparse scores: entry (" + std::to_string(e.i) + ", " + std::to_string(e.j) +
                                  ") outside a " + std::to_string(rows) + " x " + std::to_string(cols) + " matrix");
    }
    if (k > 0 && entries[k - 1].i == e.i && entries[k - 1].j == e.j) {
      throw std::invalid_argument("sparse scores: cell (" + std::to_string(e.i) + ", " + std::to_string(e.j) +
                                  ") listed twice");
    }
    if (!std::isfinite(e.score)) throw std::invalid_argument("sparse scores: scores must be finite");
    columns_.push_back(e.j);
    values_.push_back(e.score);
    ++row_begin_[e.i + 1];
  }
  for (std::size_t i = 0; i < rows; ++i) row_begin_[i + 1] += row_begin_[i];
}

std::span<const std::uint32_t> SparseScores::row_columns(std::size_t i) const {
  return {columns_.data() + row_begin_[i], row_begin_[i + 1] - row_begin_[i]};
}
std::span<const float> SparseScores::row_values(std::size_t i) const {
  return {values_.data() + row_begin_[i], row_begin_[i + 1] - row_begin_[i]};
}

float SparseScores::at(std::size_t i, std::size_t j) const {
  const auto cols = row_columns(i);
  const auto it = std::lower_bound(cols.begin(), cols.end(), j);
  if (it != cols.end() && *it == j) return row_values(i)[static_cast<std::size_t>(it - cols.begin())];
  return background_;
}

void SparseScores::read_row(std::size_t i, std::size_t j_begin, std::size_t j_end, float* out) const {
  std::fill(out, out + (j_end - j_begin), background_);
  const auto cols = row_columns(i);
  const auto vals = row_values(i);
  for (auto it = std::lower_bound(cols.begin(), cols.end(), j_begin); it != cols.end() && *it < j_end; ++it) {
    out[*it - j_begin] = vals[static_cast<std::size_t>(it - cols.begin())];
  }
}

align::ScoreSource SparseScores::source() const {
  return align::ScoreSource(rows_, cols_, [this](std::size_t i, std::size_t jb, std::size_t je, float* out) {
    read_row(i, jb, je, out);
  });
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
  std::uint32_t find_const(std::uint32_t x) const {
    while (parent_[x] != x) x = parent_[x];
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

struct Box {
  std::size_t i0 = std::numeric_limits<std::size_t>::max(), i1 = 0;  // pass rows, inclusive
  std::size_t t0 = std::numeric_limits<std::size_t>::max(), t1 = 0;  // pass columns, inclusive
  float best = 0;
};

class SparsePass {
 public:
  SparsePass(const SparseScores& scores, const AlignConfig& config)
      : s_(scores), config_(config), m_(scores.rows()), n_(scores.cols()) {}

  std::vector<LocalAlignment> run(SparseAlignStats& stats) {
    fill();
    stats.active_cells += active_;
    // Bounding box and best value of every component.
    std::vector<std::uint32_t> box_of(uf_.size(), std::numeric_limits<std::uint32_t>::max());
    std::vector<Box> boxes;
    for (std::size_t i = 0; i < m_; ++i) {
      for (const Cell& c : rows_[i]) {
        const std::uint32_t root = uf_.find(c.id);
        if (box_of[root] == std::numeric_limits<std::uint32_t>::max()) {
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
    for (std::size_t i = 0; i < m_; ++i) {
      for (const Cell& c : rows_[i]) {
        const std::uint32_t root = uf_.find(c.id);
        const std::uint32_t b = box_of[root];
        // Each component once, at its first cell in row-major order, if it can reach the threshold.
        if (b == std::numeric_limits<std::uint32_t>::max()) continue;
        box_of[root] = std::numeric_limits<std::uint32_t>::max();
        if (boxes[b].best < floor) continue;
        ++stats.aligned_components;
        align_box(boxes[b], root, stats);
      }
    }
    // Order by score, then position; equal keys from different components (possible in the reverse
    // pass, where b_begin is the last pair's column) are put in the dense engine's order: by the
    // row-major position of the first maximal cell when each was taken.
    std::vector<Ref> order;
    for (std::size_t g = 0; g < groups_.size(); ++g) {
      for (std::size_t k = 0; k < groups_[g].alignments.size(); ++k) order.push_back({g, k, 0});
    }
    auto key_less = [&](const Ref& x, const Ref& y) {
      const LocalAlignment& a = at(x);
      const LocalAlignment& b = at(y);
      if (a.score != b.score) return a.score > b.score;
      if (a.a_begin != b.a_begin) return a.a_begin < b.a_begin;
      return a.b_begin < b.b_begin;
    };
    std::stable_sort(order.begin(), order.end(), key_less);
    for (std::size_t lo = 0; lo < order.size();) {
      std::size_t hi = lo + 1;
      while (hi < order.size() && !key_less(order[lo], order[hi])) ++hi;
      if (hi - lo > 1) {
        for (std::size_t k = lo; k < hi; ++k) order[k].first_max = first_max_key(order[k]);
        std::stable_sort(order.begin() + static_cast<std::ptrdiff_t>(lo), order.begin() + static_cast<std::ptrdiff_t>(hi),
                         [](const Ref& x, const Ref& y) { return x.first_max < y.first_max; });
      }
      lo = hi;
    }
    std::vector<LocalAlignment> out;
    out.reserve(std::min(order.size(), config_.max_alignments));
    for (const Ref& r : order) {
      if (out.size() >= config_.max_alignments) break;
      out.push_back(std::move(groups_[r.group].alignments[r.index]));
    }
    return out;
  }

 private:
  // The alignments of one component, in the order the exact engine took them, and its box.
  struct Group {
    std::size_t r0, r1, c0, c1;  // box in original coordinates, inclusive
    bool self;                   // aligned with the self band (a square box on the diagonal)
    std::uint32_t root;
    std::vector<LocalAlignment> alignments;  // in original coordinates
  };
  struct Ref {
    std::size_t group, index;
    std::uint64_t first_max;
  };
  const LocalAlignment& at(const Ref& r) const { return groups_[r.group].alignments[r.index]; }

  // Row-major position (in pass coordinates) of the component's first cell at the alignment's score,
  // just before the engine took it: the box is refilled with the component's earlier pairs used.
  std::uint64_t first_max_key(const Ref& ref) const {
    const Group& g = groups_[ref.group];
    const std::size_t rows = g.r1 - g.r0 + 1, cols = g.c1 - g.c0 + 1;
    std::vector<std::uint8_t> used(rows * cols, 0);
    const bool fwd = config_.direction == Direction::forward;
    auto box_col = [&](std::size_t c) { return fwd ? c - g.c0 : g.c1 - c; };  // box pass column of original c
    for (std::size_t k = 0; k < ref.index; ++k) {
      for (const auto& [pi, pj] : g.alignments[k].pairs) used[(pi - g.r0) * cols + box_col(pj)] = 1;
    }
    const float target = at(ref).score;
    std::vector<float> prev(cols + 1, 0.0F), cur(cols + 1, 0.0F);
    for (std::size_t r = g.r0; r <= g.r1; ++r) {
      cur[0] = 0.0F;
      for (std::size_t tb = 0; tb < cols; ++tb) {
        const std::size_t c = fwd ? g.c0 + tb : g.c1 - tb;
        float v = 0.0F;
        if (!g.self || (r >= c && r - c >= config_.min_separation)) {
          if (used[(r - g.r0) * cols + tb] == 0) v = std::max(v, prev[tb] + s_.at(r, c));
          v = std::max(v, prev[tb + 1] - config_.gap_a);
          v = std::max(v, cur[tb] - config_.gap_b);
          if (config_.cap) v = std::min(v, *config_.cap);
        }
        cur[tb + 1] = v;
        if (v == target) {
          const std::size_t t = fwd ? c : n_ - 1 - c;
          const Cell* cell = find(rows_[r], t);
          if (cell != nullptr && uf_.find_const(cell->id) == g.root) return static_cast<std::uint64_t>(r) * n_ + t;
        }
      }
      std::swap(prev, cur);
    }
    return std::numeric_limits<std::uint64_t>::max();
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

  static const Cell* find(const std::vector<Cell>& row, std::size_t col) {
    const auto it = std::lower_bound(row.begin(), row.end(), col, [](const Cell& c, std::size_t v) { return c.col < v; });
    return it != row.end() && it->col == col ? &*it : nullptr;
  }

  // The engine's first fill restricted to the cells where H can be positive.
  void fill() {
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
      std::size_t left_next = std::numeric_limits<std::size_t>::max();
      constexpr std::size_t none = std::numeric_limits<std::size_t>::max();
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
        const auto cit = std::lower_bound(cand.begin(), cand.end(), t,
                                          [](const auto& c, std::size_t v) { return c.first < v; });
        const float s = cit != cand.end() && cit->first == t ? cit->second : bg;
        const Cell* diag = prev != nullptr && t > 0 ? find(*prev, t - 1) : nullptr;
        const Cell* up = prev != nullptr ? find(*prev, t) : nullptr;
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

  std::size_t original_col(std::size_t t) const { return config_.direction == Direction::forward ? t : n_ - 1 - t; }

  void align_box(const Box& box, std::uint32_t root, SparseAlignStats& stats) {
    std::size_t r0 = box.i0, r1 = box.i1;
    std::size_t c0 = std::min(original_col(box.t0), original_col(box.t1));
    std::size_t c1 = std::max(original_col(box.t0), original_col(box.t1));
    AlignConfig cfg = config_;
    cfg.max_alignments = std::numeric_limits<std::size_t>::max();
    // Inside the self band (r - c >= sep for every cell of the box) the band plays no part; otherwise
    // the engine needs the band itself: a square box on the diagonal.
    const bool inside = !config_.self || (r0 >= c1 && r0 - c1 >= config_.min_separation);
    if (!inside) {
      r0 = c0 = std::min(r0, c0);
      r1 = c1 = std::max(r1, c1);
    } else {
      cfg.self = false;
    }
    const std::size_t rows = r1 - r0 + 1, cols = c1 - c0 + 1;
    stats.box_cells += rows * cols;
    stats.largest_box_cells = std::max(stats.largest_box_cells, rows * cols);
    const align::ScoreSource sub(rows, cols, [this, r0, c0](std::size_t i, std::size_t jb, std::size_t je, float* o) {
      s_.read_row(r0 + i, c0 + jb, c0 + je, o);
    });
    Group& group = groups_.emplace_back(Group{r0, r1, c0, c1, cfg.self, root, {}});
    for (LocalAlignment& a : align::local_alignments(sub, cfg)) {
      // Other components inside the box are aligned by their own box.
      const std::size_t gi = a.pairs.front().first + r0, gc = a.pairs.front().second + c0;
      const std::size_t t = config_.direction == Direction::forward ? gc : n_ - 1 - gc;
      const Cell* cell = find(rows_[gi], t);
      if (cell == nullptr || uf_.find(cell->id) != root) continue;
      a.a_begin += r0;
      a.a_end += r0;
      a.b_begin += c0;
      a.b_end += c0;
      for (auto& [pi, pj] : a.pairs) {
        pi += r0;
        pj += c0;
      }
      group.alignments.push_back(std::move(a));
    }
  }

  const SparseScores& s_;
  const AlignConfig& config_;
  std::size_t m_, n_;
  std::vector<std::vector<Cell>> rows_;
  UnionFind uf_;
  std::vector<Group> groups_;
  std::size_t active_ = 0;
};

void validate(const SparseScores& scores, const AlignConfig& config) {
  if (!(scores.background() < 0)) throw std::invalid_argument("sparse alignment needs a background score < 0");
  if (!(config.gap_a > 0) || !(config.gap_b > 0)) throw std::invalid_argument("sparse alignment needs gap penalties > 0");
}

}  // namespace

std::vector<LocalAlignment> sparse_local_alignments(const SparseScores& scores, const AlignConfig& config,
                                                    SparseAlignStats* stats) {
  // The engine's own checks first (same messages), on an empty matrix of the same shape.
  align::local_alignments(align::ScoreSource(scores.rows(), scores.cols(), [](std::size_t, std::size_t, std::size_t, float*) {}),
                          [&] {
                            AlignConfig c = config;
                            c.max_alignments = 0;
                            return c;
                          }());
  validate(scores, config);
  SparseAlignStats local;
  if (scores.rows() == 0 || scores.cols() == 0 || config.max_alignments == 0) return {};
  auto out = SparsePass(scores, config).run(local);
  if (stats != nullptr) *stats = local;
  return out;
}

std::vector<LocalAlignment> sparse_local_alignments_both(const SparseScores& scores, AlignConfig config,
                                                         unsigned threads, SparseAlignStats* stats) {
  AlignConfig forward = config, reverse = config;
  forward.direction = Direction::forward;
  reverse.direction = Direction::reverse;
  SparseAlignStats fs, rs;
  std::vector<LocalAlignment> fwd, rev;
  if (threads > 1) {
    auto rev_future = std::async(std::launch::async, [&] { return sparse_local_alignments(scores, reverse, &rs); });
    fwd = sparse_local_alignments(scores, forward, &fs);
    rev = rev_future.get();
  } else {
    fwd = sparse_local_alignments(scores, forward, &fs);
    rev = sparse_local_alignments(scores, reverse, &rs);
  }
  if (stats != nullptr) {
    stats->active_cells = fs.active_cells + rs.active_cells;
    stats->components = fs.components + rs.components;
    stats->aligned_components = fs.aligned_components + rs.aligned_components;
    stats->box_cells = fs.box_cells + rs.box_cells;
    stats->largest_box_cells = std::max(fs.largest_box_cells, rs.largest_box_cells);
  }
  return align::merge_directions(std::move(fwd), std::move(rev), config.max_alignments);
}

}  // namespace seqtopo::scale
