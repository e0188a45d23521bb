// DisjointSets against connected components found by a breadth-first search over the same joins, and its promise
// that a set's root is its smallest element, whatever the order of the joins.
#include <gtest/gtest.h>

#include <cstdint>
#include <queue>
#include <random>
#include <utility>
#include <vector>

#include "seqtopo/core/disjoint_sets.hpp"

namespace seqtopo {
namespace {

// The smallest element of each element's component, by breadth-first search.
std::vector<std::size_t> smallest_of_component(std::size_t n,
                                               const std::vector<std::pair<std::size_t, std::size_t>>& joins) {
  std::vector<std::vector<std::size_t>> next(n);
  for (const auto& [a, b] : joins) {
    next[a].push_back(b);
    next[b].push_back(a);
  }
  std::vector<std::size_t> smallest(n, n);
  for (std::size_t start = 0; start < n; ++start) {
    if (smallest[start] != n) continue;
    std::queue<std::size_t> queue;
    queue.push(start);
    smallest[start] = start;  // visited in increasing order: the first seen is the smallest
    while (!queue.empty()) {
      const std::size_t x = queue.front();
      queue.pop();
      for (const std::size_t y : next[x]) {
        if (smallest[y] == n) {
          smallest[y] = start;
          queue.push(y);
        }
      }
    }
  }
  return smallest;
}

TEST(DisjointSets, RootsAreTheSmallestOfEachComponentAsASearchFindsThem) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t n = 1 + rng() % 60, joins = rng() % (2 * n);
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    DisjointSets<std::uint32_t> sets;
    for (std::size_t k = 0; k < n; ++k) EXPECT_EQ(sets.add(), k);
    for (std::size_t k = 0; k < joins; ++k) {
      const std::size_t a = rng() % n, b = rng() % n;
      pairs.emplace_back(a, b);
      const bool together = sets.find(static_cast<std::uint32_t>(a)) == sets.find(static_cast<std::uint32_t>(b));
      const auto [root, absorbed] = sets.unite(static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b));
      EXPECT_EQ(root == absorbed, together);
      EXPECT_LE(root, absorbed);
    }
    const auto smallest = smallest_of_component(n, pairs);
    std::vector<std::size_t> count(n, 0);
    for (std::size_t x = 0; x < n; ++x) ++count[smallest[x]];
    for (std::size_t x = 0; x < n; ++x) {
      EXPECT_EQ(sets.find(static_cast<std::uint32_t>(x)), smallest[x]) << "trial " << trial << ", element " << x;
      EXPECT_EQ(sets.set_size(sets.find(static_cast<std::uint32_t>(x))), count[smallest[x]]);
    }
  }
}

TEST(DisjointSets, SizedAtConstructionAsIfAddedOneByOne) {
  DisjointSets<std::size_t> sets(5);
  EXPECT_EQ(sets.size(), 5U);
  sets.unite(4, 2);
  sets.unite(3, 4);
  EXPECT_EQ(sets.find(3), 2U);
  EXPECT_EQ(sets.set_size(2), 3U);
  EXPECT_EQ(sets.add(), 5U);
  EXPECT_EQ(sets.find(5), 5U);
}

}  // namespace
}  // namespace seqtopo
