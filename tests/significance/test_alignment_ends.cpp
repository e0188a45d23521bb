// Where a revisit ends: significance::trim_chance_ends on hand-built paths whose change points are known.
#include <gtest/gtest.h>

#include <map>
#include <utility>
#include <vector>

#include "seqtopo/significance/alignment_ends.hpp"

namespace seqtopo::significance {
namespace {

// Pairs (100 + k, 10 + k) (or 10 + n - 1 - k, reverse) whose cells score `cells[k]`; every other cell -1.
struct Path {
  align::LocalAlignment alignment;
  std::map<std::pair<std::size_t, std::size_t>, float> cells;
  align::ScoreSource source() const {
    return align::ScoreSource::function(200, 200, [this](std::size_t i, std::size_t j) {
      const auto it = cells.find({i, j});
      return it == cells.end() ? -1.0F : it->second;
    });
  }
};

Path path(const std::vector<float>& cells, bool reverse = false) {
  Path p;
  const std::size_t n = cells.size();
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = 100 + k, j = reverse ? 10 + n - 1 - k : 10 + k;
    p.alignment.pairs.emplace_back(i, j);
    p.cells[{i, j}] = cells[k];
  }
  p.alignment.direction = reverse ? align::Direction::reverse : align::Direction::forward;
  p.alignment.a_begin = 100;
  p.alignment.a_end = 100 + n;
  p.alignment.b_begin = 10;
  p.alignment.b_end = 10 + n;
  return p;
}

std::vector<float> revisit_with_ends(std::vector<float> head, std::size_t length, float score,
                                     const std::vector<float>& tail) {
  for (std::size_t k = 0; k < length; ++k) head.push_back(score);
  head.insert(head.end(), tail.begin(), tail.end());
  return head;
}

TEST(AlignmentEnds, ChanceTailsAreCutAtTheChangePoint) {
  // 20 revisit pairs scoring 2, with a tail gaining 1.2 over six chance cells and a head gaining 0.5 over
  // three (the chance cells average -0.75 elsewhere).
  const std::vector<float> tail{-1.1F, 0.9F, 0.2F, 0.6F, 0.2F, 0.4F}, head{0.6F, -0.4F, 0.3F};
  for (bool reverse : {false, true}) {
    const Path p = path(revisit_with_ends(head, 20, 2.0F, tail), reverse);
    const auto trimmed = trim_chance_ends(p.alignment, p.source(), 1.5, 1.5, -0.75, 6.0);
    ASSERT_EQ(trimmed.pairs.size(), 20U) << reverse;
    EXPECT_EQ(trimmed.pairs.front(), p.alignment.pairs[3]);
    EXPECT_EQ(trimmed.pairs.back(), p.alignment.pairs[22]);
    EXPECT_EQ(trimmed.a_begin, 103U);
    EXPECT_EQ(trimmed.a_end, 123U);
    EXPECT_EQ(trimmed.b_end - trimmed.b_begin, 20U);
    EXPECT_EQ(trimmed.direction, p.alignment.direction);
  }
}

TEST(AlignmentEnds, SignificantTailsAndDipsInsideARevisitStay) {
  // A tail of six cells at 1.2 is below the midpoint ((-0.75 + mean) / 2 > 1.2) but gains 7.2: no chance tail.
  const Path strong = path(revisit_with_ends({}, 20, 4.0F, std::vector<float>(6, 1.2F)));
  EXPECT_EQ(trim_chance_ends(strong.alignment, strong.source(), 1.5, 1.5, -0.75, 6.0).pairs, strong.alignment.pairs);
  // The same tail is cut when chance reaches such gains often.
  EXPECT_EQ(trim_chance_ends(strong.alignment, strong.source(), 1.5, 1.5, -0.75, 8.0).pairs.size(), 20U);
  // A weak stretch inside a long revisit: 30 pairs at 2, five at -1, 30 at 2. Nothing is cut.
  std::vector<float> dip(30, 2.0F);
  for (int k = 0; k < 5; ++k) dip.push_back(-1.0F);
  for (int k = 0; k < 30; ++k) dip.push_back(2.0F);
  const Path inside = path(dip);
  EXPECT_EQ(trim_chance_ends(inside.alignment, inside.source(), 1.5, 1.5, -0.75, 6.0).pairs, inside.alignment.pairs);
  // Too short, or no better than chance: unchanged.
  const Path two = path({2.0F, -1.0F});
  EXPECT_EQ(trim_chance_ends(two.alignment, two.source(), 1.5, 1.5, -0.75, 6.0).pairs, two.alignment.pairs);
  const Path flat = path(std::vector<float>(10, -0.8F));
  EXPECT_EQ(trim_chance_ends(flat.alignment, flat.source(), 1.5, 1.5, -0.75, 6.0).pairs, flat.alignment.pairs);
}

TEST(AlignmentEnds, GapsCostTheirPenaltyInTheTail) {
  // Ten revisit pairs at 2, then two pairs at 1.5 reached over a skipped row each: each gap costs 1.5, so the
  // tail gains nothing and is cut; without gap penalties it gains 3 and is only below the midpoint.
  Path p = path(std::vector<float>(10, 2.0F));
  for (std::size_t k = 0; k < 2; ++k) {
    const std::size_t i = 111 + 2 * k, j = 20 + k;
    p.alignment.pairs.emplace_back(i, j);
    p.cells[{i, j}] = 1.5F;
  }
  p.alignment.a_end = 114;
  p.alignment.b_end = 22;
  EXPECT_EQ(trim_chance_ends(p.alignment, p.source(), 1.5, 1.5, -0.75, 1.0).pairs.size(), 10U);
  EXPECT_EQ(trim_chance_ends(p.alignment, p.source(), 0.0, 0.0, -0.75, 1.0).pairs.size(), 12U);
}

}  // namespace
}  // namespace seqtopo::significance
