#pragma once
// The slow, obvious twin of the engine: after every alignment the whole table is filled again from
// scratch (with the used pairs forbidden), every search below runs over the whole table with dense
// flag matrices, and the reverse pass works on an explicitly reversed copy of the matrix. Same choice
// rules as documented in smith_waterman.hpp; nothing else is shared with the engine.
#include <algorithm>
#include <optional>
#include <stdexcept>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"

namespace seqtopo::test_support {

struct NaiveProblem {
  std::vector<std::vector<float>> s;  // s[i][j], rows = A, cols = B
  align::AlignConfig config;
};

namespace naive_detail {

using Flags = std::vector<std::vector<char>>;

// The filled table of one round and its tight steps (steps that attain the positive value of the cell
// they enter).
struct Table {
  std::vector<std::vector<float>> h, s;  // h: (m+1) x (n+1); s: pass-ordered scores, m x n
  Flags used;                            // m x n, pass coordinates
  std::optional<float> cap;
  float gap_a = 0, gap_b = 0;

  float clamp(float v) const { return cap ? std::min(v, *cap) : v; }
  bool diag(std::size_t i, std::size_t t) const {  // (i-1, t-1) -> (i, t)
    return i > 0 && t > 0 && h[i][t] > 0 && !used[i - 1][t - 1] && clamp(h[i - 1][t - 1] + s[i - 1][t - 1]) == h[i][t];
  }
  bool down(std::size_t i, std::size_t t) const {  // (i-1, t) -> (i, t)
    return i > 0 && h[i][t] > 0 && clamp(h[i - 1][t] - gap_a) == h[i][t];
  }
  bool right(std::size_t i, std::size_t t) const {  // (i, t-1) -> (i, t)
    return t > 0 && h[i][t] > 0 && clamp(h[i][t - 1] - gap_b) == h[i][t];
  }
};

// Cells reachable from (pi, pt) by tight steps that stay inside the rectangle [p, q].
inline Flags reach_from(const Table& tb, std::size_t pi, std::size_t pt, std::size_t qi, std::size_t qt) {
  Flags f(tb.h.size(), std::vector<char>(tb.h[0].size(), 0));
  f[pi][pt] = 1;
  for (std::size_t i = pi; i <= qi; ++i) {
    for (std::size_t t = pt; t <= qt; ++t) {
      if (i > pi && t > pt && tb.diag(i, t) && f[i - 1][t - 1]) f[i][t] = 1;
      if (i > pi && tb.down(i, t) && f[i - 1][t]) f[i][t] = 1;
      if (t > pt && tb.right(i, t) && f[i][t - 1]) f[i][t] = 1;
    }
  }
  return f;
}

// Cells of the rectangle [p, q] from which (qi, qt) is reachable by tight steps inside it.
inline Flags reach_to(const Table& tb, std::size_t pi, std::size_t pt, std::size_t qi, std::size_t qt) {
  Flags b(tb.h.size(), std::vector<char>(tb.h[0].size(), 0));
  b[qi][qt] = 1;
  for (std::size_t i = qi + 1; i-- > pi;) {
    for (std::size_t t = qt + 1; t-- > pt;) {
      if (i < qi && t < qt && tb.diag(i + 1, t + 1) && b[i + 1][t + 1]) b[i][t] = 1;
      if (i < qi && tb.down(i + 1, t) && b[i + 1][t]) b[i][t] = 1;
      if (t < qt && tb.right(i, t + 1) && b[i][t + 1]) b[i][t] = 1;
    }
  }
  return b;
}

// The documented bisection between two cells of an optimal path; appends the pairs (table cells).
inline void bisect(const Table& tb, std::size_t pi, std::size_t pt, std::size_t qi, std::size_t qt,
                   std::vector<std::pair<std::size_t, std::size_t>>& cells) {
  if (qi == pi || qt == pt) return;
  if (qi == pi + 1) {
    // routes through the row: right along row pi to column c, then down, then right along row qi
    auto right_run = [&](std::size_t i, std::size_t from, std::size_t to) {  // steps into from+1 .. to
      for (std::size_t t = from + 1; t <= to; ++t) {
        if (!tb.right(i, t)) return false;
      }
      return true;
    };
    for (std::size_t c = pt; c <= qt; ++c) {
      if (right_run(pi, pt, c) && tb.down(qi, c) && right_run(qi, c, qt)) return;  // gap-only route
    }
    for (std::size_t c = pt + 1; c <= qt; ++c) {
      if (right_run(pi, pt, c - 1) && tb.diag(qi, c) && right_run(qi, c, qt)) {
        cells.emplace_back(qi, c);
        return;
      }
    }
    throw std::logic_error("naive bisection found no route");
  }
  const std::size_t mid = pi + (qi - pi) / 2;
  const Flags f = reach_from(tb, pi, pt, qi, qt), b = reach_to(tb, pi, pt, qi, qt);
  std::optional<std::size_t> cross;
  for (std::size_t c = pt; c <= qt; ++c) {
    if (!f[mid][c] || !b[mid][c]) continue;
    const bool enters_down = tb.down(mid, c) && f[mid - 1][c];
    const bool leaves_down = tb.down(mid + 1, c) && b[mid + 1][c];
    if (!cross || (!enters_down && leaves_down)) cross = c;
  }
  if (!cross) throw std::logic_error("naive bisection found no crossing");
  bisect(tb, pi, pt, mid, *cross, cells);
  bisect(tb, mid, *cross, qi, qt, cells);
}

}  // namespace naive_detail

inline std::vector<align::LocalAlignment> naive_local_alignments(const NaiveProblem& p) {
  const auto& c = p.config;
  const std::size_t m = p.s.size();
  const std::size_t n = m == 0 ? 0 : p.s[0].size();
  const bool rev = c.direction == align::Direction::reverse;
  // pass matrix: column t of the pass is column (rev ? n-1-t : t) of B
  auto orig = [&](std::size_t t) { return rev ? n - 1 - t : t; };
  auto valid = [&](std::size_t i, std::size_t t) {
    if (!c.self) return true;
    const std::size_t j = orig(t);
    return i >= j + c.min_separation;
  };
  naive_detail::Table tb;
  tb.cap = c.cap;
  tb.gap_a = c.gap_a;
  tb.gap_b = c.gap_b;
  tb.used.assign(m, std::vector<char>(n, 0));
  tb.h.assign(m + 1, std::vector<float>(n + 1, 0.0F));
  tb.s.assign(m, std::vector<float>(n, 0.0F));
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t t = 0; t < n; ++t) tb.s[i][t] = p.s[i][orig(t)];
  }
  auto& h = tb.h;
  std::vector<align::LocalAlignment> out;
  while (out.size() < c.max_alignments) {
    for (std::size_t i = 1; i <= m; ++i) {
      for (std::size_t t = 1; t <= n; ++t) {
        if (!valid(i - 1, t - 1)) {
          h[i][t] = 0;
          continue;
        }
        float v = 0;
        if (!tb.used[i - 1][t - 1]) v = std::max(v, h[i - 1][t - 1] + tb.s[i - 1][t - 1]);
        v = std::max(v, h[i - 1][t] - c.gap_a);
        v = std::max(v, h[i][t - 1] - c.gap_b);
        h[i][t] = tb.clamp(v);
      }
    }
    // first maximal cell in row-major order
    std::size_t bi = 0, bt = 0;
    float best = 0;
    for (std::size_t i = 1; i <= m; ++i) {
      for (std::size_t t = 1; t <= n; ++t) {
        if (h[i][t] > best) {
          best = h[i][t];
          bi = i;
          bt = t;
        }
      }
    }
    if (bi == 0 || best < c.threshold) break;
    // at the cap: the last maximal cell reachable from it by tight steps
    std::size_t ei = bi, et = bt;
    if (c.cap && best == *c.cap) {
      const auto from_first = naive_detail::reach_from(tb, bi, bt, m, n);
      for (std::size_t i = 1; i <= m; ++i) {
        for (std::size_t t = 1; t <= n; ++t) {
          if (from_first[i][t] && h[i][t] == best) {
            ei = i;
            et = t;
          }
        }
      }
    }
    // the latest zero cell from which an optimal alignment (a tight path through positive cells) reaches the end
    naive_detail::Flags to_end(m + 1, std::vector<char>(n + 1, 0));
    to_end[ei][et] = 1;
    for (std::size_t i = ei + 1; i-- > 0;) {
      for (std::size_t t = et + 1; t-- > 0;) {
        if (h[i][t] <= 0) continue;
        if (i < m && t < n && tb.diag(i + 1, t + 1) && to_end[i + 1][t + 1]) to_end[i][t] = 1;
        if (i < m && tb.down(i + 1, t) && to_end[i + 1][t]) to_end[i][t] = 1;
        if (t < n && tb.right(i, t + 1) && to_end[i][t + 1]) to_end[i][t] = 1;
      }
    }
    std::optional<std::pair<std::size_t, std::size_t>> start;
    for (std::size_t i = 0; i < ei; ++i) {
      for (std::size_t t = 0; t < et; ++t) {
        if (h[i][t] == 0 && tb.diag(i + 1, t + 1) && to_end[i + 1][t + 1]) start = {{i, t}};
      }
    }
    if (!start) throw std::logic_error("naive alignment has no start");
    std::vector<std::pair<std::size_t, std::size_t>> cells;
    naive_detail::bisect(tb, start->first, start->second, ei, et, cells);

    align::LocalAlignment a;
    a.direction = c.direction;
    a.score = best;
    for (auto [i, t] : cells) {
      a.pairs.emplace_back(i - 1, orig(t - 1));
      tb.used[i - 1][t - 1] = 1;
    }
    a.a_begin = a.pairs.front().first;
    a.a_end = a.pairs.back().first + 1;
    a.b_begin = n;
    a.b_end = 0;
    for (auto [x, y] : a.pairs) {
      a.b_begin = std::min(a.b_begin, y);
      a.b_end = std::max(a.b_end, y + 1);
    }
    out.push_back(std::move(a));
  }
  return out;
}

}  // namespace seqtopo::test_support
