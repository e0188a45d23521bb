#pragma once
// Random sparse alignment problems for the tests of the sparse mode: scattered candidates plus planted
// revisits, with cap, threshold, gaps, self band; symmetric when self.
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/scale/sparse_alignment.hpp"

namespace seqtopo::scale::test_problems {

struct Problem {
  SparseScores scores;
  align::AlignConfig config;
};

// Scattered candidates plus planted diagonal and anti-diagonal runs (the revisits); symmetric when self.
inline Problem random_problem(std::mt19937& rng, bool integer_scores) {
  std::uniform_int_distribution<std::size_t> size(1, 90);
  Problem p;
  auto& c = p.config;
  c.self = std::bernoulli_distribution(0.5)(rng);
  const std::size_t rows = size(rng), cols = c.self ? rows : size(rng);
  std::set<std::pair<std::uint32_t, std::uint32_t>> cells;
  std::vector<SparseEntry> entries;
  auto value = [&](float lo, float hi) {
    const float v = std::uniform_real_distribution<float>(lo, hi)(rng);
    return integer_scores ? std::round(v) : v;
  };
  auto add = [&](std::size_t i, std::size_t j, float v) {
    if (i >= rows || j >= cols) return;
    if (!cells.insert({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)}).second) return;
    entries.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j), v});
    if (c.self && i != j && cells.insert({static_cast<std::uint32_t>(j), static_cast<std::uint32_t>(i)}).second) {
      entries.push_back({static_cast<std::uint32_t>(j), static_cast<std::uint32_t>(i), v});
    }
  };
  const double density = std::uniform_real_distribution<double>(0.0, 0.15)(rng);
  for (std::size_t i = 0; i < rows; ++i) {
    for (std::size_t j = 0; j < cols; ++j) {
      if (std::bernoulli_distribution(density)(rng)) add(i, j, value(-3.0F, 4.0F));
    }
  }
  const int runs = std::uniform_int_distribution<int>(0, 4)(rng);
  for (int r = 0; r < runs; ++r) {
    const std::size_t i0 = std::uniform_int_distribution<std::size_t>(0, rows - 1)(rng);
    const std::size_t j0 = std::uniform_int_distribution<std::size_t>(0, cols - 1)(rng);
    const std::size_t len = std::uniform_int_distribution<std::size_t>(2, 30)(rng);
    const bool anti = std::bernoulli_distribution(0.5)(rng);
    for (std::size_t k = 0; k < len; ++k) {
      if (std::bernoulli_distribution(0.1)(rng)) continue;  // a hole: the run needs a gap or a mismatch
      const std::size_t j = anti ? j0 - k : j0 + k;         // wraps out of range when anti runs off
      add(i0 + k, j, value(0.5F, 3.0F));
    }
  }
  const float background = integer_scores ? -static_cast<float>(std::uniform_int_distribution<int>(1, 2)(rng))
                                          : std::uniform_real_distribution<float>(-2.0F, -0.2F)(rng);
  p.scores = SparseScores(rows, cols, background, std::move(entries));
  const float gaps[] = {0.5F, 1.0F, 1.5F, 2.0F, 3.0F};
  std::uniform_int_distribution<int> gap_pick(0, 4);
  c.gap_a = gaps[gap_pick(rng)];
  c.gap_b = std::bernoulli_distribution(0.5)(rng) ? c.gap_a : gaps[gap_pick(rng)];
  if (std::bernoulli_distribution(0.6)(rng)) c.cap = static_cast<float>(std::uniform_int_distribution<int>(2, 12)(rng));
  c.threshold =
      std::bernoulli_distribution(0.4)(rng) ? 0.0F : static_cast<float>(std::uniform_int_distribution<int>(1, 6)(rng));
  c.min_separation = std::uniform_int_distribution<std::size_t>(1, 12)(rng);
  return p;
}

}  // namespace seqtopo::scale::test_problems
