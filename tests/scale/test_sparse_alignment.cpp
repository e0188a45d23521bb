// The sparse alignment against the exact engine on the equivalent dense matrix (candidate scores at
// the candidates, the background elsewhere), on random cases with cap, threshold, gaps, self band and
// both directions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <random>
#include <set>
#include <vector>

#include "scale/random_sparse_problems.hpp"
#include "seqtopo/align/smith_waterman.hpp"
#include "seqtopo/scale/sparse_alignment.hpp"

namespace seqtopo::align {
// Readable failure messages.
inline void PrintTo(const LocalAlignment& a, std::ostream* os) {
  *os << to_string(a.direction) << " score " << a.score << " A[" << a.a_begin << "," << a.a_end << ") B[" << a.b_begin
      << "," << a.b_end << ") pairs " << a.pairs.size();
}
}  // namespace seqtopo::align

namespace seqtopo::scale {
namespace {

using test_problems::Problem;
using test_problems::random_problem;

TEST(SparseAlignment, EqualsDenseEngineOnRandomCases) {
  std::mt19937 rng(20261123);
  std::size_t nonempty = 0;
  for (int trial = 0; trial < 700; ++trial) {
    const Problem p = random_problem(rng, trial % 2 == 0);
    const auto dense = p.scores.source();
    const auto expected = align::local_alignments_both(dense, p.config, 1);
    const auto got = sparse_local_alignments_both(p.scores, p.config, trial % 3 == 0 ? 2U : 1U);
    if (got != expected) {
      std::size_t k = 0;
      while (k < got.size() && k < expected.size() && got[k] == expected[k]) ++k;
      ADD_FAILURE() << "trial " << trial << " rows " << p.scores.rows() << " self " << p.config.self
                    << ": first difference at " << k << " of " << expected.size() << " / " << got.size() << ": got "
                    << (k < got.size() ? ::testing::PrintToString(got[k]) : "-") << " expected "
                    << (k < expected.size() ? ::testing::PrintToString(expected[k]) : "-");
      return;
    }
    nonempty += expected.empty() ? 0 : 1;
    // One pass alone: the same set, ordered by score then position.
    for (const auto dir : {align::Direction::forward, align::Direction::reverse}) {
      auto cfg = p.config;
      cfg.direction = dir;
      auto want = align::local_alignments(dense, cfg);
      std::stable_sort(want.begin(), want.end(), [](const auto& x, const auto& y) {
        if (x.score != y.score) return x.score > y.score;
        if (x.a_begin != y.a_begin) return x.a_begin < y.a_begin;
        return x.b_begin < y.b_begin;
      });
      ASSERT_EQ(sparse_local_alignments(p.scores, cfg), want) << "trial " << trial;
    }
  }
  EXPECT_GT(nonempty, 200U);  // the cases are not trivially empty
}

TEST(SparseAlignment, VisitsFarFewerCellsThanTheMatrix) {
  // A 3000 x 3000 self matrix with one planted 200-frame revisit and sparse noise.
  const std::size_t n = 3000;
  std::mt19937 rng(1);
  std::vector<SparseEntry> entries;
  std::set<std::pair<std::uint32_t, std::uint32_t>> seen;
  auto add = [&](std::size_t i, std::size_t j, float v) {
    if (seen.insert({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)}).second) {
      entries.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j), v});
    }
  };
  for (std::size_t k = 0; k < 200; ++k) {
    add(2000 + k, 500 + k, 1.5F);
    add(500 + k, 2000 + k, 1.5F);
  }
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 5; ++k) {
      const std::size_t j = std::uniform_int_distribution<std::size_t>(0, n - 1)(rng);
      const float v = std::uniform_real_distribution<float>(-1.0F, 1.0F)(rng);
      add(i, j, v);
      add(j, i, v);
    }
  }
  const SparseScores scores(n, n, -0.5F, entries);
  align::AlignConfig config;
  config.gap_a = config.gap_b = 1.5F;
  config.cap = 40.0F;
  config.threshold = 8.0F;
  config.self = true;
  config.min_separation = 10;
  SparseAlignStats stats;
  const auto got = sparse_local_alignments_both(scores, config, 2, &stats);
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got.front().a_begin, 2000U);
  EXPECT_EQ(got.front().b_begin, 500U);
  EXPECT_LT(stats.active_cells + stats.box_cells, n * n / 20);
  EXPECT_EQ(got, align::local_alignments_both(scores.source(), config));
}

TEST(SparseAlignment, RejectsSettingsWithoutDecay) {
  const SparseScores zero_background(4, 4, 0.0F, {});
  EXPECT_THROW(sparse_local_alignments(zero_background, {}), std::invalid_argument);
  const SparseScores scores(4, 4, -1.0F, {{1, 2, 3.0F}});
  align::AlignConfig no_gap;
  no_gap.gap_a = 0;
  EXPECT_THROW(sparse_local_alignments(scores, no_gap), std::invalid_argument);
  EXPECT_THROW(SparseScores(4, 4, -1.0F, {{4, 0, 1.0F}}), std::invalid_argument);
  EXPECT_THROW(SparseScores(4, 4, -1.0F, {{1, 1, 1.0F}, {1, 1, 2.0F}}), std::invalid_argument);
  EXPECT_EQ(scores.at(1, 2), 3.0F);
  EXPECT_EQ(scores.at(2, 1), -1.0F);
}

}  // namespace
}  // namespace seqtopo::scale
