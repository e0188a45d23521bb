// best_parallel_path against a brute force over the shifts, and on a band of tied diagonals.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "seqtopo/align/parallel_path.hpp"

namespace seqtopo {
namespace {

using align::LocalAlignment;

// A monotone path of `length` pairs from (i0, j0) with random gap steps; reverse paths go down in j.
LocalAlignment random_path(std::mt19937& rng, std::size_t rows, std::size_t cols, bool reverse) {
  LocalAlignment a;
  a.direction = reverse ? align::Direction::reverse : align::Direction::forward;
  std::uniform_int_distribution<int> step(0, 5);
  std::size_t i = std::uniform_int_distribution<std::size_t>(rows / 2, rows / 2 + 5)(rng);
  std::size_t j = reverse ? std::uniform_int_distribution<std::size_t>(cols / 2, cols - 3)(rng)
                          : std::uniform_int_distribution<std::size_t>(2, cols / 4)(rng);
  for (int k = 0; k < 12 && i < rows && j < cols; ++k) {
    a.pairs.emplace_back(i, j);
    const int s = step(rng);
    i += 1 + (s == 0 ? 1 : 0);
    const std::size_t dj = 1 + (s == 1 ? 1 : 0);
    if (reverse && j < dj) break;
    j = reverse ? j - dj : j + dj;
  }
  return align::pairs_between(a, 0, a.pairs.size() - 1);
}

TEST(ParallelPath, MatchesABruteForceOverTheShifts) {
  std::mt19937 rng(3);
  std::normal_distribution<float> cell(0.0F, 1.0F);
  for (int trial = 0; trial < 400; ++trial) {
    const std::size_t n = 40;
    std::vector<float> values(n * n);
    for (auto& v : values) v = cell(rng);
    const auto scores = align::ScoreSource::dense(values, n, n);
    align::AlignConfig search;
    search.self = trial % 2 == 0;
    search.min_separation = 3;
    const LocalAlignment a = random_path(rng, n, n, trial % 3 == 0);
    // The engine's own path is always inside its search.
    for (const auto& [i, j] : a.pairs) search.self = search.self && i >= j + search.min_separation;
    const std::size_t reach = static_cast<std::size_t>(trial % 4);
    // Brute force: every shift in the documented order of preference (0, -1, +1, -2, ...), the first best wins.
    long best = 0;
    double best_sum = -1e300;
    for (long step = 0; step <= static_cast<long>(reach); ++step) {
      for (const long d : step == 0 ? std::vector<long>{0} : std::vector<long>{-step, step}) {
        double sum = 0;
        bool inside = true;
        for (const auto& [i, j] : a.pairs) {
          const long c = static_cast<long>(j) + d;
          if (c < 0 || c >= static_cast<long>(n) || (search.self && static_cast<long>(i) - c < 3)) {
            inside = false;
            break;
          }
          sum += values[i * n + static_cast<std::size_t>(c)];
        }
        if (inside && (d == 0 || sum > best_sum)) {
          best = d;
          best_sum = sum;
        }
      }
    }
    const LocalAlignment moved = align::best_parallel_path(a, scores, search, reach);
    ASSERT_EQ(moved.pairs.size(), a.pairs.size());
    for (std::size_t k = 0; k < a.pairs.size(); ++k) {
      ASSERT_EQ(moved.pairs[k].first, a.pairs[k].first);
      ASSERT_EQ(static_cast<long>(moved.pairs[k].second), static_cast<long>(a.pairs[k].second) + best) << trial;
    }
    EXPECT_EQ(static_cast<long>(moved.b_begin), static_cast<long>(a.b_begin) + best);
    EXPECT_EQ(moved.a_begin, a.a_begin);
    EXPECT_EQ(moved.score, a.score);
  }
}

TEST(ParallelPath, MovesAPathOnTheSideOfABandToItsCentre) {
  // Diagonals i - j = 19, 20, 21 all positive (a smooth revisit), 20 the best: a path traced along 21, as a
  // capped plateau's tie-breaking may leave it, moves to 20; without reach it stays.
  const std::size_t n = 60;
  std::vector<float> values(n * n, -1.0F);
  for (std::size_t i = 20; i < n; ++i) {
    values[i * n + (i - 20)] = 1.0F;
    values[i * n + (i - 19)] = 0.6F;
    if (i >= 21) values[i * n + (i - 21)] = 0.6F;
  }
  LocalAlignment a;
  for (std::size_t i = 30; i < 50; ++i) a.pairs.emplace_back(i, i - 21);
  a = align::pairs_between(a, 0, a.pairs.size() - 1);
  align::AlignConfig search;
  search.self = true;
  search.min_separation = 10;
  const auto scores = align::ScoreSource::dense(values, n, n);
  const LocalAlignment moved = align::best_parallel_path(a, scores, search, 3);
  EXPECT_EQ(moved.pairs.front(), std::make_pair(std::size_t{30}, std::size_t{10}));
  EXPECT_EQ(moved.b_end, 30U);
  EXPECT_EQ(align::best_parallel_path(a, scores, search, 0), a);
  // A shift that would put pairs closer than min_separation to the self diagonal is not taken.
  search.min_separation = 21;
  EXPECT_EQ(align::best_parallel_path(a, scores, search, 3), a);
}

}  // namespace
}  // namespace seqtopo
