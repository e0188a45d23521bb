// Algorithm C (Hunt-Szymanski through the longest increasing subsequence) against dynamic programming.
#include <gtest/gtest.h>

#include "naive_string_dp.hpp"
#include "seqtopo/strings/lcs_by_lis.hpp"

namespace seqtopo::strings {
namespace {

void expect_common_subsequence(std::string_view p, std::string_view t, const CommonSubsequence& c) {
  ASSERT_EQ(c.pairs.size(), c.length);
  ASSERT_EQ(c.symbols.size(), c.length);
  for (std::size_t k = 0; k < c.pairs.size(); ++k) {
    const auto [i, j] = c.pairs[k];
    ASSERT_LT(i, p.size());
    ASSERT_LT(j, t.size());
    EXPECT_EQ(p[i], t[j]);
    EXPECT_EQ(c.symbols[k], p[i]);
    if (k > 0) {
      EXPECT_LT(c.pairs[k - 1].first, i);
      EXPECT_LT(c.pairs[k - 1].second, j);
    }
  }
}

TEST(LcsByLis, WorkedExample) {
  const auto c = lcs_by_lis("vABvC", "AvBCv");
  EXPECT_EQ(c.length, 3U);
  expect_common_subsequence("vABvC", "AvBCv", c);
  EXPECT_EQ(c.indel_distance(5, 5), 4U);
  EXPECT_EQ(lcs_by_lis("", "abc").length, 0U);
  EXPECT_EQ(lcs_by_lis("AAA", "BBB").length, 0U);
}

TEST(LcsByLis, LongestIncreasingSubsequence) {
  const std::vector<std::size_t> values = {5, 1, 4, 2, 3, 9, 7, 8};
  const auto lis = longest_increasing_subsequence(values);
  ASSERT_EQ(lis.size(), 5U);  // 1 2 3 7 8
  for (std::size_t k = 1; k < lis.size(); ++k) {
    EXPECT_LT(lis[k - 1], lis[k]);
    EXPECT_LT(values[lis[k - 1]], values[lis[k]]);
  }
}

TEST(LcsByLis, MatchesDynamicProgrammingAndIndelDistance) {
  std::mt19937 rng(31337);
  for (int trial = 0; trial < 3000; ++trial) {
    const int colours = trial % 3 == 0 ? 1 : 15;
    const std::string p = test_support::random_fingerprint(rng, 0, 50, colours);
    const std::string t = std::bernoulli_distribution(0.5)(rng) ? test_support::mutate(rng, p, 0.3, colours)
                                                                : test_support::random_fingerprint(rng, 0, 50, colours);
    const auto c = lcs_by_lis(p, t);
    ASSERT_EQ(c.length, test_support::naive_lcs(p, t)) << p << " / " << t;
    const std::size_t indel = test_support::naive_indel_distance(p, t);
    ASSERT_EQ(c.length, (p.size() + t.size() - indel) / 2);
    EXPECT_EQ(c.indel_distance(p.size(), t.size()), indel);
    expect_common_subsequence(p, t, c);
  }
}

}  // namespace
}  // namespace seqtopo::strings
