// Suffix array and constant-time longest common extension against direct comparison.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "naive_string_dp.hpp"
#include "seqtopo/strings/longest_common_extension.hpp"

namespace seqtopo::strings {
namespace {

TEST(SuffixArray, SortsSuffixes) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<std::uint32_t> s(std::uniform_int_distribution<std::size_t>(0, 60)(rng));
    for (auto& x : s) x = std::uniform_int_distribution<std::uint32_t>(0, trial % 3 == 0 ? 1 : 5)(rng);
    std::vector<std::uint32_t> want(s.size());
    std::iota(want.begin(), want.end(), 0U);
    std::sort(want.begin(), want.end(), [&](std::uint32_t a, std::uint32_t b) {
      return std::lexicographical_compare(s.begin() + a, s.end(), s.begin() + b, s.end());
    });
    ASSERT_EQ(suffix_array(s), want);
  }
}

TEST(LongestCommonExtension, MatchesDirectComparison) {
  std::mt19937 rng(6);
  for (int trial = 0; trial < 400; ++trial) {
    const std::string a = test_support::random_fingerprint(rng, 0, 40, trial % 2 ? 1 : 4);
    const std::string b = trial % 4 == 0 ? a + a : test_support::random_fingerprint(rng, 0, 40, trial % 2 ? 1 : 4);
    const LongestCommonExtension lce(a, b);
    for (std::size_t i = 0; i <= a.size(); ++i) {
      for (std::size_t j = 0; j <= b.size(); ++j) {
        std::size_t want = 0;
        while (i + want < a.size() && j + want < b.size() && a[i + want] == b[j + want]) ++want;
        ASSERT_EQ(lce(i, j), want) << a << " / " << b << " at " << i << "," << j;
      }
    }
    EXPECT_THROW(lce(a.size() + 1, 0), std::out_of_range);
  }
}

}  // namespace
}  // namespace seqtopo::strings
