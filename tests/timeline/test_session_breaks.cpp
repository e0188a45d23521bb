// Session breaks from the frames' times and their look (timeline/session_breaks.hpp): the gaps against a direct
// reading of the rule, ranks against counting every frame, and pauses told from cuts on walks with known truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <stdexcept>
#include <vector>

#include "seqtopo/timeline/session_breaks.hpp"

namespace seqtopo::timeline {
namespace {

TEST(TimeGaps, HandWorked) {
  // Intervals 1 1 1 12 1 1 0.5 30: median 1; 12 and 30 are at least 10 times it and 1 s.
  const std::vector<double> times{0, 1, 2, 3, 15, 16, 17, 17.5, 47.5};
  const auto gaps = time_gaps(times);
  ASSERT_EQ(gaps.size(), 2U);
  EXPECT_EQ(gaps[0].frame, 4U);
  EXPECT_DOUBLE_EQ(gaps[0].gap, 12);
  EXPECT_DOUBLE_EQ(gaps[0].median_interval, 1);
  EXPECT_EQ(gaps[1].frame, 8U);
  EXPECT_DOUBLE_EQ(gaps[1].gap, 30);
}

TEST(TimeGaps, ShortGapsOfAFastCameraAreNotGapsUnlessASecondLong) {
  // 30 Hz with a 0.5 s dropout: 15 times the median interval, but under a second.
  std::vector<double> times;
  for (int k = 0; k < 100; ++k) times.push_back(k / 30.0 + (k >= 50 ? 0.5 : 0.0));
  EXPECT_TRUE(time_gaps(times).empty());
  times.back() += 5;  // a 5 s pause before the last frame
  const auto gaps = time_gaps(times);
  ASSERT_EQ(gaps.size(), 1U);
  EXPECT_EQ(gaps[0].frame, 99U);
}

// n frame times: intervals of mean 1 s, one in 20 forty times longer.
std::vector<double> random_times(std::mt19937& rng, std::size_t n) {
  std::vector<double> times{0};
  std::exponential_distribution<double> step(1.0);
  std::bernoulli_distribution jump(0.05);
  while (times.size() < n) times.push_back(times.back() + (jump(rng) ? 40 * step(rng) : step(rng)));
  return times;
}

TEST(TimeGaps, AgainstTheRuleReadDirectly) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t n = 3 + rng() % 60;
    const std::vector<double> times = random_times(rng, n);
    std::vector<double> intervals;
    for (std::size_t k = 1; k < n; ++k) intervals.push_back(times[k] - times[k - 1]);
    std::vector<double> sorted = intervals;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[sorted.size() / 2];  // the upper median, as the rule reads it
    std::vector<std::size_t> expected;
    for (std::size_t k = 0; k < intervals.size(); ++k) {
      if (intervals[k] >= 10 * median && intervals[k] >= 1) expected.push_back(k + 1);
    }
    std::vector<std::size_t> got;
    for (const auto& g : time_gaps(times)) {
      got.push_back(g.frame);
      EXPECT_DOUBLE_EQ(g.median_interval, median);
    }
    EXPECT_EQ(got, expected) << "trial " << trial;
  }
}

TEST(TimeGaps, NoneWithoutAnInterval) {
  EXPECT_TRUE(time_gaps(std::vector<double>{}).empty());
  EXPECT_TRUE(time_gaps(std::vector<double>{0, 100}).empty());
  EXPECT_TRUE(time_gaps(std::vector<double>{5, 5, 5, 100}).empty());  // median interval 0: no scale
}

TEST(TimeGaps, RefusesTimesThatAreNotARecordingsOwn) {
  EXPECT_THROW(time_gaps(std::vector<double>{0, 2, 1}), std::invalid_argument);
  EXPECT_THROW(time_gaps(std::vector<double>{0, std::numeric_limits<double>::quiet_NaN(), 1}), std::invalid_argument);
}

// A random symmetric similarity.
std::vector<std::vector<double>> random_matrix(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::vector<double>> m(n, std::vector<double>(n));
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j <= i; ++j) m[i][j] = m[j][i] = std::round(u(rng) * 50) / 50;  // ties too
  }
  return m;
}

TEST(NeighbourRank, AgainstCountingEveryFrame) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const std::size_t n = 5 + seed * 7;
    const auto m = random_matrix(n, seed);
    const Similarity s = [&m](std::size_t i, std::size_t j) { return m[i][j]; };
    for (std::size_t a = 0; a + 1 < n; a += 3) {
      const std::size_t b = a + 1;
      std::size_t others = 0, below_a = 0, below_b = 0;
      for (std::size_t j = 0; j < n; ++j) {
        if (j == a || j == b) continue;
        ++others;
        below_a += m[a][j] < m[a][b];
        below_b += m[b][j] < m[a][b];
      }
      const double expected = static_cast<double>(std::min(below_a, below_b)) / static_cast<double>(others);
      EXPECT_DOUBLE_EQ(neighbour_rank(s, a, b, 0, n), expected) << seed << " " << a;
    }
  }
}

TEST(NeighbourRank, ASampleOfColumnsIsEvenlySpread) {
  // Against 10 of 100 frames: frames 0, 10, ..., 90, and the rank counts those alone.
  const auto m = random_matrix(100, 3);
  const Similarity s = [&m](std::size_t i, std::size_t j) { return m[i][j]; };
  SessionBreakConfig config;
  config.rank_columns = 10;
  const std::size_t a = 45, b = 46;
  std::size_t below_a = 0, below_b = 0;
  for (std::size_t j = 0; j < 100; j += 10) {
    below_a += m[a][j] < m[a][b];
    below_b += m[b][j] < m[a][b];
  }
  EXPECT_DOUBLE_EQ(neighbour_rank(s, a, b, 0, 100, config), static_cast<double>(std::min(below_a, below_b)) / 10);
}

// A walk along a line: frame k at position x[k]; two frames are as alike as they are near (plus noise of its own
// per pair), as consecutive frames of a recording are.
struct Walk {
  std::vector<double> x;
  std::vector<std::vector<double>> noise;
  double operator()(std::size_t i, std::size_t j) const { return -std::abs(x[i] - x[j]) + noise[i][j]; }
};

Walk walk(const std::vector<double>& x, unsigned seed) {
  Walk w{x, std::vector<std::vector<double>>(x.size(), std::vector<double>(x.size()))};
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, 0.3);
  for (std::size_t i = 0; i < x.size(); ++i) {
    for (std::size_t j = 0; j <= i; ++j) w.noise[i][j] = w.noise[j][i] = g(rng);
  }
  return w;
}

TEST(LooksLikeNeighbours, APauseIsOneSessionACutIsNot) {
  for (unsigned seed = 1; seed <= 10; ++seed) {
    // 0..99 along the line; then 100 frames elsewhere (a cut), or on from where the walk stopped (a pause).
    std::vector<double> cut, pause;
    for (int k = 0; k < 100; ++k) cut.push_back(k), pause.push_back(k);
    for (int k = 0; k < 100; ++k) cut.push_back(1000 + k), pause.push_back(100 + k);
    const Walk c = walk(cut, seed), p = walk(pause, seed);
    EXPECT_FALSE(looks_like_neighbours(std::cref(c), 99, 100, 0, 200)) << seed;
    EXPECT_TRUE(looks_like_neighbours(std::cref(p), 99, 100, 0, 200)) << seed;
  }
}

TEST(LooksLikeNeighbours, AFrameOfNoInformationSaysNothing) {
  std::vector<double> x;
  for (int k = 0; k < 50; ++k) x.push_back(k);
  const Walk w = walk(x, 1);
  EXPECT_TRUE(looks_like_neighbours(std::cref(w), 20, 21, 0, 50));
  EXPECT_FALSE(looks_like_neighbours(std::cref(w), 20, 21, 0, 50, [](std::size_t f) { return f == 21; }));
}

TEST(LooksLikeNeighbours, WhereNeighboursAreHardlyAlikeItTakesMoreThanChance) {
  // Frames that are all unrelated (a very low frame rate): the recording's own steps rank at chance, but two
  // unrelated frames are not taken for neighbours unless they rank at 0.9 or above (about one pair in ten).
  const auto m = random_matrix(200, 11);
  const Similarity s = [&m](std::size_t i, std::size_t j) { return m[i][j]; };
  std::size_t taken = 0;
  for (std::size_t a = 0; a + 1 < 200; ++a) {
    const bool neighbours = looks_like_neighbours(s, a, a + 1, 0, 200);
    EXPECT_EQ(neighbours, neighbour_rank(s, a, a + 1, 0, 200) >= 0.9) << a;
    taken += neighbours;
  }
  EXPECT_LT(taken, 35U);  // about 20 of 199 expected
}

// The rows a frame brings online: its similarity to every earlier frame.
std::vector<std::vector<float>> rows_of(const Walk& w, std::size_t t) {
  std::vector<float> row(t);
  for (std::size_t j = 0; j < t; ++j) row[j] = static_cast<float>(w(t, j));
  return {row};
}

TEST(OnlineBreakFinder, GapsByTheIntervalsBeforeAgainstTheRuleReadDirectly) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 100; ++trial) {
    const std::size_t n = 3 + rng() % 80;
    const std::vector<double> times = random_times(rng, n);
    OnlineBreakFinder finder;
    finder.start_session();
    for (std::size_t t = 0; t < n; ++t) {
      // Rows of one value: no step ranks above 0, so every gap is a break.
      const auto gap = finder.add(times[t], {std::vector<float>(t, 0.0F)});
      std::optional<double> expected;
      if (t >= 3) {
        std::vector<double> before;
        for (std::size_t k = 1; k < t; ++k) before.push_back(times[k] - times[k - 1]);
        std::sort(before.begin(), before.end());
        const double median = before[before.size() / 2];
        const double interval = times[t] - times[t - 1];
        if (median > 0 && interval >= 10 * median && interval >= 1) expected = median;
      }
      ASSERT_EQ(gap.has_value(), expected.has_value()) << "trial " << trial << " frame " << t;
      if (gap) {
        EXPECT_DOUBLE_EQ(gap->gap.median_interval, *expected);
        EXPECT_EQ(gap->gap.frame, t);
        EXPECT_TRUE(gap->session_break);
      }
    }
  }
}

TEST(OnlineBreakFinder, APauseIsOneSessionACutIsNotAsOffline) {
  for (unsigned seed = 1; seed <= 10; ++seed) {
    std::vector<double> cut, pause, times;
    for (int k = 0; k < 100; ++k) cut.push_back(k), pause.push_back(k), times.push_back(k);
    for (int k = 0; k < 100; ++k) cut.push_back(1000 + k), pause.push_back(100 + k), times.push_back(5000 + k);
    for (const bool is_cut : {true, false}) {
      const Walk w = walk(is_cut ? cut : pause, seed);
      OnlineBreakFinder finder;
      finder.start_session();
      std::vector<OnlineBreakFinder::Gap> gaps;
      for (std::size_t t = 0; t < 200; ++t) {
        if (auto g = finder.add(times[t], rows_of(w, t))) gaps.push_back(*g);
      }
      ASSERT_EQ(gaps.size(), 1U) << seed;
      EXPECT_EQ(gaps[0].gap.frame, 100U);
      EXPECT_EQ(gaps[0].session_break, is_cut) << seed;
      // The offline rule on the whole walk says the same.
      EXPECT_EQ(!looks_like_neighbours(std::cref(w), 99, 100, 0, 200), is_cut) << seed;
    }
  }
}

TEST(OnlineBreakFinder, EachSessionHasItsOwnIntervalsAndNoStepIntoIt) {
  OnlineBreakFinder finder;
  finder.start_session();
  for (std::size_t t = 0; t < 5; ++t) EXPECT_FALSE(finder.add(0.1 * static_cast<double>(t), {std::vector<float>(t)}));
  finder.start_session();  // a new input starting an hour later: not a gap, its first interval is its own
  EXPECT_FALSE(finder.add(3600.0, {std::vector<float>(5)}));
  EXPECT_FALSE(finder.add(3610.0, {std::vector<float>(6)}));
  EXPECT_FALSE(finder.add(3620.0, {std::vector<float>(7)}));
  EXPECT_TRUE(finder.add(4000.0, {std::vector<float>(8)}).has_value());
}

TEST(OnlineBreakFinder, RefusesRowsAndTimesThatDoNotFit) {
  OnlineBreakFinder finder;
  finder.start_session();
  EXPECT_THROW(finder.add(0.0, {std::vector<float>(1)}), std::invalid_argument);
  EXPECT_FALSE(finder.add(1.0, {std::vector<float>{}}));
  EXPECT_THROW(finder.add(0.5, {std::vector<float>(1)}), std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::timeline
