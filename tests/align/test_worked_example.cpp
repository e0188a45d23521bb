// Hand-worked examples in the style of the mapping paper's Fig. 3, with the alignments written out.
#include <gtest/gtest.h>

#include <string>

#include "seqtopo/align/smith_waterman.hpp"

namespace seqtopo {
namespace {

align::ScoreSource letters(const std::string& a, const std::string& b, float match, float mismatch) {
  return align::ScoreSource::function(a.size(), b.size(), [a, b, match, mismatch](std::size_t i, std::size_t j) {
    return a[i] == b[j] ? match : mismatch;
  });
}

// Fig. 3's strings, A = a b e d and B = e c d a, with match +2, mismatch -1, gap 1.
// The filled table (rows A, columns B; row/column 0 are zeros):
//          e  c  d  a
//     a    0  0  0  2
//     b    0  0  0  1
//     e    2  1  0  0
//     d    1  1  3  2
// The best cell is (d, d) = 3; the only optimal alignment ending there is d-d (+2) <- gap over c (-1)
// <- e-e (+2), starting at the zero cell (b, before e):
//     A:  e - d
//     B:  e c d        score 2 - 1 + 2 = 3
// With that pair set forbidden, the next best is the lone a-a at 2 (row a, column a) - b-a is a
// mismatch, so it cannot grow. The e-e and d-d cells are used, nothing else scores.
TEST(WorkedExample, PaperFigure3Strings) {
  align::AlignConfig config;
  config.gap_a = config.gap_b = 1.0F;
  const auto found = align::local_alignments(letters("abed", "ecda", 2.0F, -1.0F), config);
  ASSERT_EQ(found.size(), 2U);
  EXPECT_EQ(found[0].score, 3.0F);
  EXPECT_EQ(found[0].pairs, (std::vector<std::pair<std::size_t, std::size_t>>{{2, 0}, {3, 2}}));
  EXPECT_EQ(found[0].a_begin, 2U);
  EXPECT_EQ(found[0].a_end, 4U);
  EXPECT_EQ(found[0].b_begin, 0U);
  EXPECT_EQ(found[0].b_end, 3U);
  EXPECT_EQ(found[1].score, 2.0F);
  EXPECT_EQ(found[1].pairs, (std::vector<std::pair<std::size_t, std::size_t>>{{0, 3}}));
}

// The reverse pass on the same strings: A is walked forwards while B is walked backwards, i.e. A is
// aligned with B' = a d c e (B' column t is B column 3 - t). Table (rows A, columns B'):
//          a  d  c  e
//     a    2  1  0  0
//     b    1  1  0  0
//     e    0  0  0  2
//     d    0  2  1  1
// No two matches chain up (every diagonal step between them is a mismatch), so there are three
// single-pair alignments of score 2. The first maximum in row order is a-a; no tight step leads from
// it to another 2, so it ends there: a(A0)-a(B3). With that pair forbidden, row a is all zeros and
// row d stays 0 2 1 1 (d-c and d-e are gaps after d-d and e-e: 2 - 1), so the next first maximum
// is e-e: e(A2)-e(B0), then d(A3)-d(B2).
TEST(WorkedExample, PaperFigure3StringsReversePass) {
  align::AlignConfig config;
  config.gap_a = config.gap_b = 1.0F;
  config.direction = align::Direction::reverse;
  const auto found = align::local_alignments(letters("abed", "ecda", 2.0F, -1.0F), config);
  ASSERT_EQ(found.size(), 3U);
  for (const auto& a : found) EXPECT_EQ(a.score, 2.0F);
  EXPECT_EQ(found[0].pairs, (std::vector<std::pair<std::size_t, std::size_t>>{{0, 3}}));
  EXPECT_EQ(found[1].pairs, (std::vector<std::pair<std::size_t, std::size_t>>{{2, 0}}));
  EXPECT_EQ(found[2].pairs, (std::vector<std::pair<std::size_t, std::size_t>>{{3, 2}}));
}

// A revisit with a skipped image and a capped score:
//   A = x a b c d e y      (a b c d e seen once)
//   B = a b c z d e        (seen again, with an extra image z between c and d)
// match +1, mismatch -1, gap 0.5, cap 3: a-a 1, b-b 2, c-c 3 (cap), skip z: 3 - 0.5 = 2.5,
// d-d min(3.5, 3) = 3, e-e 3. The first maximum in row order is c-c, but tight steps (c-c -> skip z
// -> d-d -> e-e) lead on to more cells at the cap, so the alignment ends at the last of them, e-e,
// and keeps every pair.
TEST(WorkedExample, GapAndCap) {
  align::AlignConfig config;
  config.gap_a = config.gap_b = 0.5F;
  config.cap = 3.0F;
  const auto found = align::local_alignments(letters("xabcdey", "abczde", 1.0F, -1.0F), config);
  ASSERT_FALSE(found.empty());
  EXPECT_EQ(found[0].score, 3.0F);
  EXPECT_EQ(found[0].pairs, (std::vector<std::pair<std::size_t, std::size_t>>{{1, 0}, {2, 1}, {3, 2}, {4, 4}, {5, 5}}));
  EXPECT_EQ(found[0].b_end, 6U);
}

}  // namespace
}  // namespace seqtopo
