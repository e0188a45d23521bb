// Invariants of the engine, checked on fixed-seed random problems.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "random_problems.hpp"
#include "seqtopo/align/smith_waterman.hpp"

namespace seqtopo {
namespace {

using align::Direction;
using align::LocalAlignment;

TEST(Properties, ScoresPositiveAboveThresholdAndBelowCap) {
  std::mt19937 rng(1);
  for (int k = 0; k < 500; ++k) {
    const auto p = test_support::random_problem(rng);
    const auto& c = p.naive.config;
    float previous = std::numeric_limits<float>::infinity();
    for (const auto& a : align::local_alignments(p.source(), c)) {
      EXPECT_GT(a.score, 0.0F);
      EXPECT_GE(a.score, c.threshold);
      if (c.cap) {
        EXPECT_LE(a.score, *c.cap);
      }
      EXPECT_LE(a.score, previous) << "alignments must come best first";
      previous = a.score;
    }
  }
}

TEST(Properties, AlignmentsNeverShareAPairAndPairsAreMonotone) {
  std::mt19937 rng(2);
  for (int k = 0; k < 500; ++k) {
    const auto p = test_support::random_problem(rng);
    const auto& c = p.naive.config;
    std::set<std::pair<std::size_t, std::size_t>> seen;
    for (const auto& a : align::local_alignments(p.source(), c)) {
      ASSERT_FALSE(a.pairs.empty());
      for (std::size_t q = 0; q < a.pairs.size(); ++q) {
        auto [i, j] = a.pairs[q];
        EXPECT_TRUE(seen.insert({i, j}).second) << "pair used twice";
        EXPECT_LT(i, p.rows);
        EXPECT_LT(j, p.cols);
        EXPECT_GE(i, a.a_begin);
        EXPECT_LT(i, a.a_end);
        EXPECT_GE(j, a.b_begin);
        EXPECT_LT(j, a.b_end);
        if (c.self) {
          EXPECT_GE(i, j + c.min_separation) << "pair inside the excluded band";
        }
        if (q > 0) {
          auto [pi, pj] = a.pairs[q - 1];
          EXPECT_GT(i, pi);
          if (c.direction == Direction::forward) {
            EXPECT_GT(j, pj);
          } else {
            EXPECT_LT(j, pj);
          }
        }
      }
    }
  }
}

TEST(Properties, CapAboveBestScoreChangesNothing) {
  std::mt19937 rng(3);
  for (int k = 0; k < 500; ++k) {
    auto p = test_support::random_problem(rng);
    p.naive.config.cap.reset();
    const auto uncapped = align::local_alignments(p.source(), p.naive.config);
    if (uncapped.empty()) continue;
    auto capped_config = p.naive.config;
    capped_config.cap = uncapped.front().score + 0.5F + static_cast<float>(k % 3);
    EXPECT_EQ(align::local_alignments(p.source(), capped_config), uncapped);
    // A cap equal to the best score changes no value, but the best alignment now ends on a plateau at
    // the cap and is taken whole: same score, ending no earlier.
    capped_config.cap = uncapped.front().score;
    const auto at_cap = align::local_alignments(p.source(), capped_config);
    ASSERT_FALSE(at_cap.empty());
    EXPECT_EQ(at_cap.front().score, uncapped.front().score);
    EXPECT_GE(at_cap.front().a_end, uncapped.front().a_end);
  }
}

TEST(Properties, CapStopsSpillOverBetweenDistantMatches) {
  // Two strong matching stretches separated by a long poor one: without a cap the score carries the
  // alignment across the gap; with the cap it splits into two alignments (mapping paper, IV-B).
  const std::size_t n = 60;
  std::vector<float> s(n * n, -0.5F);
  for (std::size_t i = 0; i < n; ++i) {
    const bool matching = i < 20 || i >= 40;
    s[i * n + i] = matching ? 1.0F : -0.5F;
  }
  align::AlignConfig config;
  config.gap_a = config.gap_b = 2.0F;
  config.threshold = 5.0F;
  const auto source = align::ScoreSource::dense(s, n, n);
  const auto uncapped = align::local_alignments(source, config);
  ASSERT_FALSE(uncapped.empty());
  EXPECT_EQ(uncapped.front().a_begin, 0U);
  EXPECT_EQ(uncapped.front().a_end, n);
  config.cap = 8.0F;
  const auto capped = align::local_alignments(source, config);
  ASSERT_EQ(capped.size(), 2U);
  std::set<std::pair<std::size_t, std::size_t>> ranges;
  for (const auto& a : capped) ranges.insert({a.a_begin, a.a_end});
  EXPECT_EQ(ranges, (std::set<std::pair<std::size_t, std::size_t>>{{0, 20}, {40, 60}}));
}

TEST(Properties, ReversePassOnReversedBEqualsForwardPass) {
  std::mt19937 rng(4);
  for (int k = 0; k < 500; ++k) {
    auto p = test_support::random_problem(rng);
    auto config = p.naive.config;
    config.self = false;  // the reversed copy is no longer a self-similarity matrix
    config.direction = Direction::forward;
    const auto forward = align::local_alignments(p.source(), config);

    std::vector<float> reversed(p.dense.size());
    for (std::size_t i = 0; i < p.rows; ++i) {
      for (std::size_t j = 0; j < p.cols; ++j) reversed[i * p.cols + j] = p.dense[i * p.cols + (p.cols - 1 - j)];
    }
    config.direction = Direction::reverse;
    auto backward = align::local_alignments(align::ScoreSource::dense(reversed, p.rows, p.cols), config);
    ASSERT_EQ(backward.size(), forward.size());
    for (std::size_t q = 0; q < forward.size(); ++q) {
      // map the reverse result on reversed B back to columns of the reversed matrix
      auto& b = backward[q];
      for (auto& pair : b.pairs) pair.second = p.cols - 1 - pair.second;
      EXPECT_EQ(b.pairs, forward[q].pairs);
      EXPECT_EQ(b.score, forward[q].score);
    }
  }
}

TEST(Properties, BothDirectionsDeterministicAcrossThreadCounts) {
  std::mt19937 rng(5);
  for (int k = 0; k < 200; ++k) {
    const auto p = test_support::random_problem(rng, 40);
    const auto one = align::local_alignments_both(p.source(), p.naive.config, 1);
    const auto two = align::local_alignments_both(p.source(), p.naive.config, 2);
    const auto eight = align::local_alignments_both(p.source(), p.naive.config, 8);
    EXPECT_EQ(one, two);
    EXPECT_EQ(one, eight);
    // and it is the merge of the two single passes
    auto config = p.naive.config;
    config.direction = Direction::forward;
    std::size_t expected = align::local_alignments(p.source(), config).size();
    config.direction = Direction::reverse;
    expected += align::local_alignments(p.source(), config).size();
    EXPECT_EQ(one.size(), std::min(expected, p.naive.config.max_alignments));
  }
}

TEST(Properties, SelfAlignmentFindsRevisitOnceNotTwice) {
  // A sequence that repeats itself: frames 0..9 are seen again as 20..29.
  const std::size_t n = 30;
  std::vector<float> s(n * n, -1.0F);
  for (std::size_t i = 0; i < n; ++i) {
    s[i * n + i] = 1.0F;
    if (i < 10) s[i * n + i + 20] = s[(i + 20) * n + i] = 1.0F;
  }
  align::AlignConfig config;
  config.self = true;
  config.min_separation = 5;
  config.threshold = 3.0F;
  const auto found = align::local_alignments(align::ScoreSource::dense(s, n, n), config);
  ASSERT_EQ(found.size(), 1U);
  EXPECT_EQ(found[0].a_begin, 20U);
  EXPECT_EQ(found[0].b_begin, 0U);
  EXPECT_EQ(found[0].pairs.size(), 10U);
  EXPECT_EQ(found[0].score, 10.0F);
}

TEST(Properties, ReverseSelfAlignmentFindsPathWalkedBack) {
  // Out along a corridor (frames 0..14) and back (frames 15..29): frame k revisits frame 29-k.
  const std::size_t n = 30;
  std::vector<float> s(n * n, -1.0F);
  for (std::size_t i = 0; i < n; ++i) {
    s[i * n + i] = 1.0F;
    s[i * n + (n - 1 - i)] = 1.0F;
  }
  align::AlignConfig config;
  config.self = true;
  config.min_separation = 4;
  config.threshold = 3.0F;
  config.direction = Direction::forward;
  EXPECT_TRUE(align::local_alignments(align::ScoreSource::dense(s, n, n), config).empty());
  config.direction = Direction::reverse;
  const auto found = align::local_alignments(align::ScoreSource::dense(s, n, n), config);
  ASSERT_EQ(found.size(), 1U);
  // pairs (i, 29 - i) with i - (29 - i) >= 4: i from 17 to 29
  EXPECT_EQ(found[0].pairs.front(), (std::pair<std::size_t, std::size_t>{17, 12}));
  EXPECT_EQ(found[0].pairs.back(), (std::pair<std::size_t, std::size_t>{29, 0}));
  EXPECT_EQ(found[0].b_begin, 0U);
  EXPECT_EQ(found[0].b_end, 13U);
}

TEST(Properties, RejectsMisuse) {
  std::vector<float> s(6, 1.0F);
  const auto source = align::ScoreSource::dense(s, 2, 3);
  align::AlignConfig config;
  config.self = true;
  EXPECT_THROW(align::local_alignments(source, config), std::invalid_argument);
  config.self = false;
  config.gap_a = -1.0F;
  EXPECT_THROW(align::local_alignments(source, config), std::invalid_argument);
  config.gap_a = 1.0F;
  config.cap = 0.0F;
  EXPECT_THROW(align::local_alignments(source, config), std::invalid_argument);
  EXPECT_THROW(align::ScoreSource::dense(s, 3, 3), std::invalid_argument);
  // nothing to align is a normal, empty result
  EXPECT_TRUE(align::local_alignments(align::ScoreSource::dense(std::span<const float>{}, 0, 0)).empty());
}

}  // namespace
}  // namespace seqtopo
