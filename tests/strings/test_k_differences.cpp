// Algorithm B (Landau-Vishkin) against the infix dynamic programming table and edlib's infix mode.
#include <edlib.h>
#include <gtest/gtest.h>

#include "naive_string_dp.hpp"
#include "seqtopo/strings/k_differences.hpp"

namespace seqtopo::strings {
namespace {

using test_support::random_fingerprint;

TEST(KDifferences, WorkedExample) {
  const auto r = k_differences("vAB", "CCvABvAAB", {1});
  std::vector<std::pair<std::size_t, std::size_t>> got;
  for (const auto& o : r.occurrences) got.emplace_back(o.end, o.differences);
  const std::vector<std::pair<std::size_t, std::size_t>> want = {{4, 1}, {5, 0}, {6, 1}, {7, 1}, {8, 1}, {9, 1}};
  EXPECT_EQ(got, want);
  EXPECT_EQ(r.best_differences(), 0U);
  EXPECT_FALSE(k_differences("vvvv", "ABAB", {2}).best_differences().has_value());  // "no occurrence" is a result
}

TEST(KDifferences, EmptyPatternOccursEverywhere) {
  const auto r = k_differences("", "AB", {0});
  ASSERT_EQ(r.occurrences.size(), 3U);
  EXPECT_EQ(r.best_differences(), 0U);
}

TEST(KDifferences, MatchesInfixDynamicProgramming) {
  std::mt19937 rng(4242);
  std::size_t occurrences = 0, none = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const std::string t = random_fingerprint(rng, 0, 50, trial % 2 ? 3 : 8);
    std::string p;
    if (!t.empty() && std::bernoulli_distribution(0.6)(rng)) {
      const std::size_t a = std::uniform_int_distribution<std::size_t>(0, t.size() - 1)(rng);
      const std::size_t len = std::uniform_int_distribution<std::size_t>(0, t.size() - a)(rng);
      p = test_support::mutate(rng, t.substr(a, len), 0.3, trial % 2 ? 3 : 8);
    } else {
      p = random_fingerprint(rng, 0, 20, trial % 2 ? 3 : 8);
    }
    const std::size_t k = std::uniform_int_distribution<std::size_t>(0, 12)(rng);
    const auto got = k_differences(p, t, {k});
    const auto table = test_support::naive_infix(p, t);
    std::vector<Occurrence> want;
    for (std::size_t j = 0; j < table.size(); ++j) {
      if (table[j] <= k) want.push_back({j, table[j]});
    }
    ASSERT_EQ(got.occurrences.size(), want.size()) << p << " in " << t << " k=" << k;
    for (std::size_t i = 0; i < want.size(); ++i) {
      ASSERT_EQ(got.occurrences[i].end, want[i].end) << p << " in " << t << " k=" << k;
      ASSERT_EQ(got.occurrences[i].differences, want[i].differences) << p << " in " << t << " k=" << k;
    }
    (want.empty() ? none : occurrences)++;
  }
  EXPECT_GT(occurrences, 1000U);
  EXPECT_GT(none, 300U);
}

TEST(KDifferences, AgreesWithEdlibInfixMode) {
  std::mt19937 rng(99);
  for (int trial = 0; trial < 3000; ++trial) {
    const std::string t = random_fingerprint(rng, 1, 80, 15);
    const std::string p = test_support::mutate(rng, t.substr(t.size() / 3, 1 + t.size() / 3), 0.3, 15);
    if (p.empty()) continue;
    const int k = std::uniform_int_distribution<int>(0, 15)(rng);
    const EdlibAlignResult ref = edlibAlign(p.data(), static_cast<int>(p.size()), t.data(), static_cast<int>(t.size()),
                                            edlibNewAlignConfig(k, EDLIB_MODE_HW, EDLIB_TASK_LOC, nullptr, 0));
    ASSERT_EQ(ref.status, EDLIB_STATUS_OK);
    const auto got = k_differences(p, t, {static_cast<std::size_t>(k)});
    ASSERT_EQ(got.best_differences().has_value(), ref.editDistance >= 0) << p << " in " << t << " k=" << k;
    if (ref.editDistance >= 0) {
      EXPECT_EQ(*got.best_differences(), static_cast<std::size_t>(ref.editDistance));
      // edlib lists the (inclusive) ends of the best occurrences.
      std::vector<std::size_t> best_ends, edlib_ends;
      for (const auto& o : got.occurrences) {
        if (o.differences == static_cast<std::size_t>(ref.editDistance)) best_ends.push_back(o.end);
      }
      for (int i = 0; i < ref.numLocations; ++i)
        edlib_ends.push_back(static_cast<std::size_t>(ref.endLocations[i] + 1));
      EXPECT_EQ(best_ends, edlib_ends) << p << " in " << t;
    }
    edlibFreeAlignResult(ref);
  }
}

}  // namespace
}  // namespace seqtopo::strings
