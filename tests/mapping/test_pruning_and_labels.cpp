// Pruning and labeling on hand-built alignment sets, including the mapping paper's three inconsistent
// alignments (section IV-C).
#include <gtest/gtest.h>

#include <set>

#include "seqtopo/mapping/place_labels.hpp"
#include "seqtopo/mapping/pruning.hpp"

namespace seqtopo::mapping {
namespace {

using align::Direction;
using align::LocalAlignment;

// A forward alignment pairing later images i0.. with earlier images j0.. one to one.
LocalAlignment diagonal(std::size_t i0, std::size_t j0, std::size_t length, float score) {
  LocalAlignment a;
  a.score = score;
  for (std::size_t k = 0; k < length; ++k) a.pairs.emplace_back(i0 + k, j0 + k);
  a.a_begin = i0;
  a.a_end = i0 + length;
  a.b_begin = j0;
  a.b_end = j0 + length;
  return a;
}

std::vector<std::pair<std::size_t, std::size_t>> as_pairs(const PruningResult& r) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (const auto& p : r.pairs) out.emplace_back(p.i, p.j);
  return out;
}

// The paper's example, written with 1-based image numbers as in the text, as (later, earlier) pairs:
//   alignment 1: 1..5 with 11..15, alignment 2: 11..15 with 21..25, alignment 3: 1..5 with 22..26.
// Without pruning, transitivity chains 4 = 14 = 24 = 3 (via alignment 3) and so on: every image of
// the three stretches ends up in one place.
TEST(PaperExample, WithoutPruningEverythingCollapses) {
  const std::vector<LocalAlignment> alignments = {diagonal(11, 1, 5, 5), diagonal(21, 11, 5, 5), diagonal(22, 1, 5, 5)};
  std::vector<std::pair<std::size_t, std::size_t>> all;
  for (const auto& a : alignments) all.insert(all.end(), a.pairs.begin(), a.pairs.end());
  const auto labels = label_places(27, all);
  std::set<PlaceLabel> distinct;
  for (std::size_t img : {1, 2, 3, 4, 5, 11, 12, 13, 14, 15, 21, 22, 23, 24, 25, 26}) distinct.insert(labels[img]);
  EXPECT_EQ(distinct.size(), 1U);
}

// With pruning: columns 1..5 are claimed by alignments 1 and 3 (both 5 pairs, same score); the tie
// goes to the earlier one (alignment 1), so alignment 3 loses all its pairs. Labels become the
// consistent triples {1, 11, 21}, {2, 12, 22}, ... {5, 15, 25}, and image 26 stays alone.
TEST(PaperExample, PruningRemovesTheInconsistentAlignment) {
  const std::vector<LocalAlignment> alignments = {diagonal(11, 1, 5, 5), diagonal(21, 11, 5, 5), diagonal(22, 1, 5, 5)};
  const auto pruned = prune_per_column(alignments);
  EXPECT_EQ(pruned.kept, (std::vector<bool>{true, true, false}));
  EXPECT_EQ(pruned.retained_count, (std::vector<std::size_t>{5, 5, 0}));
  const auto labels = label_places(27, as_pairs(pruned));
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(labels[1 + k], labels[11 + k]);
    EXPECT_EQ(labels[11 + k], labels[21 + k]);
    if (k > 0) {
      EXPECT_NE(labels[1 + k], labels[k]);
    }
  }
  EXPECT_NE(labels[26], labels[25]);
  EXPECT_NE(labels[26], labels[5]);
}

TEST(Pruning, PaperRuleLongestAlignmentWinsEachColumnAndPartialCoverage) {
  // A long alignment over columns 0..9 and a short one over columns 8..11 (overlap 8..9).
  const std::vector<LocalAlignment> alignments = {diagonal(30, 8, 4, 9), diagonal(20, 0, 10, 6)};
  PruningConfig paper;
  paper.rank = PruningConfig::Rank::length_then_score;
  const auto pruned = prune_per_column(alignments, paper);
  // Columns 8, 9 go to the longer alignment (index 1) despite its lower score; the short one keeps
  // columns 10, 11 = half of its pairs, which meets the default 0.5 fraction.
  EXPECT_EQ(pruned.kept, (std::vector<bool>{true, true}));
  EXPECT_EQ(pruned.retained_count, (std::vector<std::size_t>{2, 10}));
  std::set<std::pair<std::size_t, std::size_t>> pairs;
  for (const auto& p : pruned.pairs) pairs.insert({p.i, p.j});
  EXPECT_TRUE(pairs.count({32, 10}));
  EXPECT_FALSE(pairs.count({30, 8}));
  EXPECT_TRUE(pairs.count({28, 8}));

  paper.min_retained_fraction = 0.75;
  const auto strict_pruned = prune_per_column(alignments, paper);
  EXPECT_EQ(strict_pruned.kept, (std::vector<bool>{false, true}));
  for (const auto& p : strict_pruned.pairs) EXPECT_EQ(p.alignment, 1U);
}

TEST(Pruning, DefaultRuleScoreFirstThenLength) {
  // The same pair of alignments: by default the higher score (index 0) takes the shared columns 8, 9,
  // and the long one keeps 8 of its 10 pairs.
  const std::vector<LocalAlignment> alignments = {diagonal(30, 8, 4, 9), diagonal(20, 0, 10, 6)};
  const auto pruned = prune_per_column(alignments);
  EXPECT_EQ(pruned.kept, (std::vector<bool>{true, true}));
  EXPECT_EQ(pruned.retained_count, (std::vector<std::size_t>{4, 8}));
  // Equal (capped) scores: the longest wins, as in the paper.
  const std::vector<LocalAlignment> capped = {diagonal(30, 8, 4, 40), diagonal(20, 0, 10, 40)};
  EXPECT_EQ(prune_per_column(capped).retained_count, (std::vector<std::size_t>{2, 10}));
}

TEST(Pruning, GapColumnStillClaimed) {
  // The long alignment skips column 3 (a gap); a short alignment pairing column 3 loses it.
  LocalAlignment long_one = diagonal(20, 0, 3, 8);
  for (std::size_t k = 4; k < 8; ++k) long_one.pairs.emplace_back(19 + k, k);
  long_one.a_end = 27;
  long_one.b_end = 8;
  const LocalAlignment short_one = diagonal(40, 3, 1, 2);
  const auto pruned = prune_per_column({long_one, short_one});
  EXPECT_EQ(pruned.kept, (std::vector<bool>{true, false}));
}

TEST(Labels, FirstAppearanceOrderAndValidation) {
  const auto labels = label_places(6, {{5, 1}, {4, 0}});
  EXPECT_EQ(labels, (std::vector<PlaceLabel>{0, 1, 2, 3, 0, 1}));
  EXPECT_THROW(label_places(3, {{3, 0}}), std::invalid_argument);
  EXPECT_EQ(label_places(0, {}).size(), 0U);
}

TEST(Labels, AgreesWithBruteForceComponents) {
  // Random pair sets: labels equal iff connected (checked by repeated relaxation).
  std::uint32_t state = 12345;
  auto next = [&] { return state = state * 1664525U + 1013904223U; };
  for (int round = 0; round < 200; ++round) {
    const std::size_t n = 1 + next() % 40;
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    for (std::size_t k = next() % 30; k > 0; --k) pairs.emplace_back(next() % n, next() % n);
    std::vector<std::size_t> comp(n);
    for (std::size_t k = 0; k < n; ++k) comp[k] = k;
    for (bool changed = true; changed;) {
      changed = false;
      for (auto [a, b] : pairs) {
        const std::size_t m = std::min(comp[a], comp[b]);
        if (comp[a] != m || comp[b] != m) {
          comp[a] = comp[b] = m;
          changed = true;
        }
      }
    }
    const auto labels = label_places(n, pairs);
    for (std::size_t a = 0; a < n; ++a) {
      for (std::size_t b = 0; b < n; ++b) EXPECT_EQ(labels[a] == labels[b], comp[a] == comp[b]);
    }
  }
}

}  // namespace
}  // namespace seqtopo::mapping
