// The islands of a growing table against a map-based reference: random rows of runs sharing start cells, each
// island's best cell and the row at which it dies; the best-k sample against a sort.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <random>
#include <vector>

#include "seqtopo/significance/online_islands.hpp"

namespace seqtopo::significance {
namespace {

TEST(OnlineIslands, DeadIslandsAreThoseTheNewestRowNoLongerCarries) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> value(-1.0F, 3.0F);
  std::uniform_int_distribution<int> start(0, 30);
  OnlineIslands islands;
  std::map<std::uint64_t, Island> live;  // the reference: each start's best (first of equal ones, earlier rows first)
  std::vector<std::pair<std::uint64_t, Island>> died, expected;
  for (std::size_t frame = 0; frame < 200; ++frame) {
    std::vector<float> row(25);
    std::vector<std::uint64_t> starts(25);
    for (std::size_t j = 0; j < row.size(); ++j) {
      row[j] = value(rng);
      starts[j] = j > 0 && rng() % 3 != 0 ? starts[j - 1] : static_cast<std::uint64_t>(start(rng) + 100 * (frame / 20));
    }
    std::map<std::uint64_t, Island> next;
    for (std::size_t j = 0; j < row.size(); ++j) {
      if (row[j] <= 0) continue;
      auto [it, added] = next.try_emplace(starts[j], Island{row[j], frame, j});
      if (!added && row[j] > it->second.best) it->second = {row[j], frame, j};
    }
    for (const auto& [s, island] : live) {
      if (auto it = next.find(s); it != next.end()) {
        if (island.best >= it->second.best) it->second = island;
      } else {
        expected.emplace_back(s, island);
      }
    }
    live = next;
    islands.advance(row, starts, frame, [&](std::uint64_t s, const Island& island) { died.emplace_back(s, island); });
    ASSERT_EQ(islands.live().islands.size(), live.size()) << frame;
    for (const auto& [s, island] : live) {
      const Island* got = islands.live().find(s);
      ASSERT_NE(got, nullptr);
      EXPECT_EQ(got->best, island.best);
      EXPECT_EQ(got->i, island.i);
      EXPECT_EQ(got->j, island.j);
    }
  }
  const auto by_start = [](const auto& a, const auto& b) {
    return a.first < b.first || (a.first == b.first && a.second.i < b.second.i);
  };
  std::sort(died.begin(), died.end(), by_start);
  std::sort(expected.begin(), expected.end(), by_start);
  ASSERT_EQ(died.size(), expected.size());
  EXPECT_GT(died.size(), 100U);
  for (std::size_t k = 0; k < died.size(); ++k) {
    EXPECT_EQ(died[k].first, expected[k].first);
    EXPECT_EQ(died[k].second.best, expected[k].second.best);
  }
}

TEST(BestIslands, KeepsTheBestKOfAStream) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0, 100);
  BestIslands best(16);
  std::vector<std::pair<double, double>> all;
  for (int k = 0; k < 500; ++k) {
    const std::pair<double, double> v{u(rng), u(rng)};
    all.push_back(v);
    best.offer(v);
  }
  std::sort(all.begin(), all.end(), std::greater<>());
  all.resize(16);
  EXPECT_EQ(best.best(), all);
  EXPECT_EQ(best.offered(), 500U);
  best.clear();
  EXPECT_EQ(best.size(), 0U);
  EXPECT_EQ(best.offered(), 0U);
}

}  // namespace
}  // namespace seqtopo::significance
