// Nearest-neighbour candidates against brute force, their determinism, and the sparse score matrix
// against the streamed (dense-equal) score.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include "seqtopo/scale/sparse_candidates.hpp"

namespace seqtopo::scale {
namespace {

// Clustered descriptors: frames revisit a few hundred places with noise (what an index is for).
std::vector<float> clustered(std::size_t n, std::size_t dim, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(0.0F, 1.0F);
  const std::size_t places = n / 8;
  std::vector<float> centre(places * dim), x(n * dim);
  for (auto& v : centre) v = g(rng);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t p = std::uniform_int_distribution<std::size_t>(0, places - 1)(rng);
    for (std::size_t t = 0; t < dim; ++t) x[i * dim + t] = centre[p * dim + t] + 0.3F * g(rng);
  }
  return x;
}

// Brute force: largest cosine first among frames at least `exclude` away.
std::vector<std::uint32_t> brute_force(const StreamingSimilarity& s, std::size_t i, std::size_t k,
                                       std::size_t exclude) {
  std::vector<std::pair<float, std::uint32_t>> all;
  for (std::size_t j = 0; j < s.size(); ++j) {
    if ((i > j ? i - j : j - i) >= exclude) all.emplace_back(-s.cosine(i, j), static_cast<std::uint32_t>(j));
  }
  std::sort(all.begin(), all.end());
  std::vector<std::uint32_t> out;
  for (std::size_t a = 0; a < std::min(k, all.size()); ++a) out.push_back(all[a].second);
  return out;
}

TEST(SparseCandidates, ExactIndexEqualsBruteForce) {
  const std::size_t n = 400, dim = 16;
  const auto x = clustered(n, dim, 1);
  const StreamingSimilarity s(x, n, dim);
  CandidateConfig config;
  config.exact = true;
  config.neighbours = 6;
  config.exclude = 5;
  const auto got = nearest_neighbours(s.normalized(), n, dim, config);
  for (std::size_t i = 0; i < n; ++i) {
    auto want = brute_force(s, i, 6, 5);
    auto have = got[i];
    // Inner products from BLAS and from the dot above may differ in the last bit: compare as sets
    // of the nearest, allowing a swap at the boundary.
    std::sort(want.begin(), want.end());
    std::sort(have.begin(), have.end());
    std::vector<std::uint32_t> common;
    std::set_intersection(want.begin(), want.end(), have.begin(), have.end(), std::back_inserter(common));
    EXPECT_GE(common.size(), 5U) << "frame " << i;
    for (const auto j : got[i]) EXPECT_GE(i > j ? i - j : j - i, 5U);
  }
}

TEST(SparseCandidates, InvertedFileHasHighRecallAndIsRepeatable) {
  const std::size_t n = 4000, dim = 32;
  const auto x = clustered(n, dim, 2);
  const StreamingSimilarity s(x, n, dim);
  CandidateConfig config;
  config.neighbours = 5;
  const auto a = nearest_neighbours(s.normalized(), n, dim, config);
  const auto b = nearest_neighbours(s.normalized(), n, dim, config);
  EXPECT_EQ(a, b);
  config.exact = true;
  const auto exact = nearest_neighbours(s.normalized(), n, dim, config);
  std::size_t found = 0, total = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::set<std::uint32_t> truth(exact[i].begin(), exact[i].end());
    for (const auto j : a[i]) found += truth.count(j);
    total += truth.size();
  }
  EXPECT_GT(static_cast<double>(found) / static_cast<double>(total), 0.9);
}

TEST(SparseCandidates, SparseScoresKeepTheExactScoreAtCandidates) {
  const std::size_t n = 500, dim = 12;
  const auto x = clustered(n, dim, 3);
  const StreamingSimilarity s(x, n, dim, {10, 0.5F, 64, 0});
  CandidateConfig config;
  config.exact = true;
  config.neighbours = 4;
  CandidateStats stats;
  const SparseScores sparse = sparse_map_scores(s, -1.0F, config, &stats);
  const auto neighbours = nearest_neighbours(s.normalized(), n, dim, config);
  std::set<std::pair<std::size_t, std::size_t>> cells;
  for (std::size_t i = 0; i < n; ++i) {
    for (const auto j : neighbours[i]) {
      cells.insert({i, j});
      cells.insert({j, i});
    }
  }
  EXPECT_EQ(sparse.entries(), cells.size());
  EXPECT_EQ(stats.pairs, cells.size());
  std::vector<float> row(n);
  for (std::size_t i = 0; i < n; ++i) {
    s.read_row(i, 0, n, row.data());
    for (std::size_t j = 0; j < n; ++j) {
      const float expected = cells.count({i, j}) != 0 ? row[j] : -1.0F;
      ASSERT_EQ(sparse.at(i, j), expected) << i << "," << j;
    }
  }
}

TEST(SparseCandidates, DiagonalReachAddsTheDiagonalsAroundEachNeighbour) {
  const std::size_t n = 300, dim = 8, reach = 2, exclude = 6;
  const auto x = clustered(n, dim, 4);
  const StreamingSimilarity s(x, n, dim, {5, 0.5F, 32, 0});
  CandidateConfig config;
  config.exact = true;
  config.neighbours = 3;
  config.exclude = exclude;
  config.diagonal_reach = reach;
  const SparseScores sparse = sparse_map_scores(s, -0.7F, config);
  const auto neighbours = nearest_neighbours(s.normalized(), n, dim, config);
  std::set<std::pair<long, long>> cells;
  for (long i = 0; i < static_cast<long>(n); ++i) {
    for (const auto j : neighbours[static_cast<std::size_t>(i)]) {
      for (long t = -static_cast<long>(reach); t <= static_cast<long>(reach); ++t) {
        for (const auto& [a, b] : {std::pair{i + t, j + t}, std::pair{i + t, j - t}}) {
          if (a < 0 || b < 0 || a >= static_cast<long>(n) || b >= static_cast<long>(n)) continue;
          if (std::abs(a - b) < static_cast<long>(exclude)) continue;
          cells.insert({a, b});
          cells.insert({b, a});
        }
      }
    }
  }
  EXPECT_EQ(sparse.entries(), cells.size());
  for (const auto& [a, b] : cells) {
    ASSERT_EQ(sparse.at(static_cast<std::size_t>(a), static_cast<std::size_t>(b)),
              s.score(static_cast<std::size_t>(a), static_cast<std::size_t>(b)));
  }
}

}  // namespace
}  // namespace seqtopo::scale
