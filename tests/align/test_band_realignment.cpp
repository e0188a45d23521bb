// realign_in_band against a second implementation (a recursion over the whole matrix) and against the paths it
// must beat: the engine's own and every sideways shift of it.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <tuple>
#include <vector>

#include "seqtopo/align/band_realignment.hpp"

namespace seqtopo {
namespace {

using align::Direction;
using align::LocalAlignment;

constexpr double kNone = -std::numeric_limits<double>::infinity();

// A monotone path of up to 10 pairs with random single gaps of either kind; reverse paths go down in j.
LocalAlignment random_path(std::mt19937& rng, std::size_t n, bool reverse) {
  LocalAlignment a;
  a.direction = reverse ? Direction::reverse : Direction::forward;
  std::uniform_int_distribution<int> kind(0, 5);
  std::size_t i = std::uniform_int_distribution<std::size_t>(n / 2, n / 2 + 4)(rng);
  std::size_t j = reverse ? std::uniform_int_distribution<std::size_t>(n / 2 - 8, n / 2 - 4)(rng)
                          : std::uniform_int_distribution<std::size_t>(2, 6)(rng);
  for (int k = 0; k < 10 && i < n && j < n; ++k) {
    a.pairs.emplace_back(i, j);
    const int s = kind(rng);
    i += s == 0 ? 2 : 1;
    const std::size_t dj = s == 1 ? 2 : 1;
    if (reverse && j < dj) break;
    j = reverse ? j - dj : j + dj;
  }
  return align::pairs_between(a, 0, a.pairs.size() - 1);
}

// The best band path's score by recursion over the matrix: the pass column t of each row's pair is within reach
// of the row's centre (the column of the pair at or before the row).
double best_in_band(const LocalAlignment& a, const std::vector<float>& values, std::size_t n,
                    const align::AlignConfig& search, std::size_t reach) {
  const bool reverse = a.direction == Direction::reverse;
  const long first = static_cast<long>(a.pairs.front().first), last = static_cast<long>(a.pairs.back().first);
  const auto original = [&](long t) { return reverse ? static_cast<long>(n) - 1 - t : t; };
  std::map<long, long> centre;
  for (long row = first, k = 0; row <= last; ++row) {
    while (k + 1 < static_cast<long>(a.pairs.size()) && static_cast<long>(a.pairs[k + 1].first) <= row) ++k;
    centre[row] = original(static_cast<long>(a.pairs[k].second));  // original() is its own inverse
  }
  const auto usable = [&](long i, long t) {
    if (i < first || i > last || t < 0 || t >= static_cast<long>(n)) return false;
    if (std::labs(t - centre[i]) > static_cast<long>(reach)) return false;
    return !search.self || i - original(t) >= static_cast<long>(search.min_separation);
  };
  std::map<std::tuple<long, long, bool>, double> memo;
  // pair = true: the best path ending in a pair at (i, t); false: ending at (i, t) by any step.
  std::function<double(long, long, bool)> best = [&](long i, long t, bool pair) -> double {
    if (!usable(i, t)) return kNone;
    const auto key = std::make_tuple(i, t, pair);
    if (auto it = memo.find(key); it != memo.end()) return it->second;
    const double cell = values[static_cast<std::size_t>(i) * n + static_cast<std::size_t>(original(t))];
    double d = i == first ? cell : cell + best(i - 1, t - 1, false);
    double v = d;
    if (!pair) v = std::max({d, best(i - 1, t, false) - search.gap_a, best(i, t - 1, false) - search.gap_b});
    memo[key] = v;
    return v;
  };
  double top = kNone;
  for (long t = 0; t < static_cast<long>(n); ++t) top = std::max(top, best(last, t, true));
  return top;
}

align::AlignConfig search_of(int trial) {
  align::AlignConfig c;
  c.gap_a = 1.5F;
  c.gap_b = trial % 2 == 0 ? 1.5F : 0.75F;
  c.self = trial % 3 != 0;
  c.min_separation = 4;
  return c;
}

TEST(BandRealignment, FindsTheBestPathInTheBandAndBeatsTheEngineAndEveryShift) {
  std::mt19937 rng(5);
  std::normal_distribution<float> cell(0.0F, 1.0F);
  const std::size_t n = 40;
  int changed = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<float> values(n * n);
    for (auto& v : values) v = cell(rng);
    const auto scores = align::ScoreSource::dense(values, n, n);
    const align::AlignConfig search = search_of(trial);
    const LocalAlignment a = random_path(rng, n, trial % 4 == 0);
    bool inside = true;  // the engine's own path is always inside its search
    for (const auto& [i, j] : a.pairs) inside = inside && (!search.self || i >= j + search.min_separation);
    if (!inside || a.pairs.size() < 2) continue;
    const std::size_t reach = 1 + static_cast<std::size_t>(trial % 3);
    const LocalAlignment got = align::realign_in_band(a, scores, search, reach);
    const double own = align::path_score(a, scores, search.gap_a, search.gap_b);
    const double score = align::path_score(got, scores, search.gap_a, search.gap_b);
    const double best = best_in_band(a, values, n, search, reach);
    // The result is the engine's path when nothing in the band beats it, else a best path of the band.
    if (got.pairs == a.pairs) {
      EXPECT_LE(best, own + 1e-9) << trial;
    } else {
      ++changed;
      EXPECT_NEAR(score, best, 1e-9) << trial;
      EXPECT_GT(score, own) << trial;
    }
    // Same rows at both ends, monotone pairs in the direction, inside the search; score and direction kept.
    EXPECT_EQ(got.pairs.front().first, a.pairs.front().first);
    EXPECT_EQ(got.pairs.back().first, a.pairs.back().first);
    EXPECT_EQ(got.direction, a.direction);
    EXPECT_EQ(got.score, a.score);
    for (std::size_t k = 1; k < got.pairs.size(); ++k) {
      EXPECT_LT(got.pairs[k - 1].first, got.pairs[k].first);
      if (a.direction == Direction::forward) {
        EXPECT_LT(got.pairs[k - 1].second, got.pairs[k].second);
      } else {
        EXPECT_GT(got.pairs[k - 1].second, got.pairs[k].second);
      }
    }
    for (const auto& [i, j] : got.pairs) EXPECT_TRUE(!search.self || i >= j + search.min_separation);
    // Every whole-path shift by less than reach (a path of the band, single gaps and all) scores no more.
    for (long d = 1 - static_cast<long>(reach); d < static_cast<long>(reach); ++d) {
      LocalAlignment shifted = a;
      bool ok = true;
      for (auto& [i, j] : shifted.pairs) {
        const long c = static_cast<long>(j) + d;
        ok = ok && c >= 0 && c + 1 < static_cast<long>(n) && (!search.self || static_cast<long>(i) - c >= 5);
        j = static_cast<std::size_t>(std::max(0L, c));
      }
      if (ok) {
        EXPECT_LE(align::path_score(shifted, scores, search.gap_a, search.gap_b), score + 1e-9) << trial;
      }
    }
  }
  EXPECT_GT(changed, 100);  // the comparison above is not vacuous
}

TEST(BandRealignment, APathZigZaggingBesideABandReturnsToItsCentre) {
  // Diagonals i - j = 19, 20, 21 all positive (a smooth revisit), 20 the best. A path that runs along 21, steps
  // to 19 and back, as a capped plateau's tie-breaking may leave it, is re-aligned onto 20; without reach, or
  // when 20 is outside the search, it stays.
  const std::size_t n = 60;
  std::vector<float> values(n * n, -1.0F);
  for (std::size_t i = 20; i < n; ++i) {
    values[i * n + (i - 20)] = 1.0F;
    values[i * n + (i - 19)] = 0.6F;
    values[i * n + (i - 21)] = 0.6F;
  }
  LocalAlignment a;
  for (std::size_t i = 30; i < 40; ++i) a.pairs.emplace_back(i, i - 21);
  a.pairs.emplace_back(41, 22);  // a gap in B... then diagonal 19
  for (std::size_t i = 42; i < 50; ++i) a.pairs.emplace_back(i, i - 19);
  a = align::pairs_between(a, 0, a.pairs.size() - 1);
  align::AlignConfig search;
  search.gap_a = search.gap_b = 1.5F;
  search.self = true;
  search.min_separation = 10;
  const auto scores = align::ScoreSource::dense(values, n, n);
  const LocalAlignment got = align::realign_in_band(a, scores, search, 3);
  ASSERT_EQ(got.pairs.size(), 20U);
  for (const auto& [i, j] : got.pairs) EXPECT_EQ(i - j, 20U);
  EXPECT_EQ(align::realign_in_band(a, scores, search, 0), a);
  // Where diagonal 20 is outside the search, a path along 21 is already the best it can be.
  LocalAlignment side;
  for (std::size_t i = 30; i < 50; ++i) side.pairs.emplace_back(i, i - 21);
  side = align::pairs_between(side, 0, side.pairs.size() - 1);
  search.min_separation = 21;
  EXPECT_EQ(align::realign_in_band(side, scores, search, 3), side);
}

TEST(BandRealignment, AReversePathKeepsItsDirection) {
  // An anti-diagonal band i + j = 69, 70, 71, 70 the best; the engine's path on 71.
  const std::size_t n = 60;
  std::vector<float> values(n * n, -1.0F);
  for (std::size_t i = 36; i < 59; ++i) {
    for (const std::size_t c : {69U, 70U, 71U}) {
      if (c > i && c - i < n) values[i * n + (c - i)] = c == 70 ? 1.0F : 0.6F;
    }
  }
  LocalAlignment a;
  a.direction = Direction::reverse;
  for (std::size_t i = 45; i < 55; ++i) a.pairs.emplace_back(i, 71 - i);
  a = align::pairs_between(a, 0, a.pairs.size() - 1);
  align::AlignConfig search;
  search.self = true;
  search.min_separation = 10;
  const LocalAlignment got = align::realign_in_band(a, align::ScoreSource::dense(values, n, n), search, 2);
  ASSERT_EQ(got.pairs.size(), 10U);
  for (const auto& [i, j] : got.pairs) EXPECT_EQ(i + j, 70U);
  EXPECT_EQ(got.direction, Direction::reverse);
}

}  // namespace
}  // namespace seqtopo
