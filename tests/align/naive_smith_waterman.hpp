#pragma once
// The slow, obvious twin of the engine: after every alignment the whole table is filled again from
// scratch (with the used pairs forbidden), the best cell is found by scanning every cell, and the
// reverse pass works on an explicitly reversed copy of the matrix. Same selection and traceback
// rules as documented in smith_waterman.hpp; nothing else is shared with the engine.
#include <algorithm>
#include <optional>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"

namespace seqtopo::testing {

struct NaiveProblem {
  std::vector<std::vector<float>> s;  // s[i][j], rows = A, cols = B
  align::AlignConfig config;
};

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
  auto clamp = [&](float v) { return c.cap ? std::min(v, *c.cap) : v; };
  std::vector<std::vector<char>> used(m, std::vector<char>(n, 0));
  std::vector<std::vector<float>> h(m + 1, std::vector<float>(n + 1, 0.0F));
  std::vector<align::LocalAlignment> out;
  while (out.size() < c.max_alignments) {
    for (std::size_t i = 1; i <= m; ++i) {
      for (std::size_t t = 1; t <= n; ++t) {
        if (!valid(i - 1, t - 1)) {
          h[i][t] = 0;
          continue;
        }
        float v = 0;
        if (!used[i - 1][t - 1]) v = std::max(v, h[i - 1][t - 1] + p.s[i - 1][orig(t - 1)]);
        v = std::max(v, h[i - 1][t] - c.gap_a);
        v = std::max(v, h[i][t - 1] - c.gap_b);
        h[i][t] = clamp(v);
      }
    }
    std::size_t bi = 0, bt = 0;
    float best = 0;
    for (std::size_t i = 1; i <= m; ++i) {
      for (std::size_t t = 1; t <= n; ++t) {
        if (h[i][t] > 0 && h[i][t] >= best) {
          best = h[i][t];
          bi = i;
          bt = t;
        }
      }
    }
    if (bi == 0 || best < c.threshold) break;
    align::LocalAlignment a;
    a.direction = c.direction;
    a.score = best;
    std::size_t i = bi, t = bt;
    while (h[i][t] > 0) {
      const float v = h[i][t];
      if (!used[i - 1][t - 1] && clamp(h[i - 1][t - 1] + p.s[i - 1][orig(t - 1)]) == v) {
        a.pairs.emplace_back(i - 1, orig(t - 1));
        used[i - 1][t - 1] = 1;  // safe: the traceback never comes back to this cell
        --i;
        --t;
      } else if (clamp(h[i - 1][t] - c.gap_a) == v) {
        --i;
      } else {
        --t;
      }
    }
    std::reverse(a.pairs.begin(), a.pairs.end());
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

}  // namespace seqtopo::testing
