#pragma once
// Fixed-seed random alignment problems for the randomized comparisons.
#include <random>
#include <vector>

#include "naive_smith_waterman.hpp"
#include "seqtopo/align/score_source.hpp"

namespace seqtopo::test_support {

struct RandomProblem {
  NaiveProblem naive;
  std::vector<float> dense;  // row-major copy for the engine
  std::size_t rows = 0, cols = 0;
  align::ScoreSource source() const { return align::ScoreSource::dense(dense, rows, cols); }
};

// Small integer scores give many ties (the hard case for choice rules); uniform floats give few.
inline RandomProblem random_problem(std::mt19937& rng, std::size_t max_size = 24) {
  std::uniform_int_distribution<std::size_t> size(1, max_size);
  RandomProblem p;
  auto& c = p.naive.config;
  c.self = std::bernoulli_distribution(0.3)(rng);
  p.rows = size(rng);
  p.cols = c.self ? p.rows : size(rng);
  const int kind = std::uniform_int_distribution<int>(0, 2)(rng);
  std::uniform_int_distribution<int> small(-3, 3);
  std::uniform_real_distribution<float> real(-1.0F, 1.0F);
  // kind 2: a planted diagonal (or anti-diagonal) of good scores on a poor background
  const bool anti = std::bernoulli_distribution(0.5)(rng);
  const std::size_t offset = std::uniform_int_distribution<std::size_t>(0, p.cols)(rng);
  p.naive.s.assign(p.rows, std::vector<float>(p.cols));
  for (std::size_t i = 0; i < p.rows; ++i) {
    for (std::size_t j = 0; j < p.cols; ++j) {
      float v;
      if (kind == 0) {
        v = static_cast<float>(small(rng));
      } else if (kind == 1) {
        v = real(rng);
      } else {
        const bool on = anti ? (i + j == offset) : (j == i + offset % 5);
        v = on ? 2.0F : static_cast<float>(small(rng) - 1) * 0.5F;
      }
      p.naive.s[i][j] = v;
    }
  }
  if (c.self) {  // a self-similarity matrix is symmetric
    for (std::size_t i = 0; i < p.rows; ++i) {
      for (std::size_t j = 0; j < i; ++j) p.naive.s[j][i] = p.naive.s[i][j];
    }
  }
  for (const auto& row : p.naive.s) p.dense.insert(p.dense.end(), row.begin(), row.end());
  const float gaps[] = {0.0F, 0.5F, 1.0F, 2.0F, 3.0F};
  std::uniform_int_distribution<int> gap_pick(0, 4);
  c.gap_a = gaps[gap_pick(rng)];
  c.gap_b = std::bernoulli_distribution(0.5)(rng) ? c.gap_a : gaps[gap_pick(rng)];
  if (std::bernoulli_distribution(0.5)(rng)) c.cap = static_cast<float>(std::uniform_int_distribution<int>(1, 8)(rng));
  c.threshold =
      std::bernoulli_distribution(0.5)(rng) ? 0.0F : static_cast<float>(std::uniform_int_distribution<int>(1, 4)(rng));
  c.min_separation = std::uniform_int_distribution<std::size_t>(1, 4)(rng);
  c.direction = std::bernoulli_distribution(0.5)(rng) ? align::Direction::forward : align::Direction::reverse;
  return p;
}

}  // namespace seqtopo::test_support
