// Cyclic variants against trying every rotation.
#include <gtest/gtest.h>

#include "naive_string_dp.hpp"
#include "seqtopo/strings/cyclic.hpp"

namespace seqtopo::strings {
namespace {

using test_support::random_fingerprint;

TEST(Cyclic, Rotate) {
  EXPECT_EQ(rotate("abcde", 2), "cdeab");
  EXPECT_EQ(rotate("abcde", 0), "abcde");
  EXPECT_EQ(rotate("", 0), "");
  EXPECT_THROW(rotate("abc", 3), std::invalid_argument);
}

TEST(Cyclic, FindsTheHeading) {
  const std::string panorama = "vAvBBvCvDDvE";
  const std::string turned = rotate(panorama, 5);
  const auto a = cyclic_banded_global_alignment(turned, panorama);
  EXPECT_EQ(a.alignment.cost, 0.0);
  EXPECT_EQ(rotate(panorama, a.rotation), turned);
  const auto b = cyclic_k_differences(turned, panorama, {2});
  EXPECT_EQ(b.best_differences(), 0U);
  EXPECT_EQ(rotate(panorama, b.rotation), turned);
  const auto c = cyclic_lcs_by_lis(turned, panorama);
  EXPECT_EQ(c.lcs.length, panorama.size());
  EXPECT_EQ(rotate(panorama, c.rotation), turned);
}

TEST(Cyclic, AlgorithmAEqualsEveryRotation) {
  std::mt19937 rng(1);
  const std::vector<EditCosts> tables = {preset_costs("A1"), preset_costs("A2-ground-floor"),
                                         preset_costs("A2-white-hall")};
  for (int trial = 0; trial < 600; ++trial) {
    const std::string t = random_fingerprint(rng, 1, 24, 5);
    const std::string p =
        test_support::mutate(rng, rotate(t, std::uniform_int_distribution<std::size_t>(0, t.size() - 1)(rng)), 0.3, 5);
    GlobalAlignmentConfig config;
    config.costs = tables[static_cast<std::size_t>(trial) % tables.size()];
    if (trial % 2) config.k = std::uniform_int_distribution<std::size_t>(0, 10)(rng);
    config.want_path = true;
    const auto got = cyclic_banded_global_alignment(p, t, config);
    GlobalAlignment want;
    std::size_t want_r = 0;
    for (std::size_t r = 0; r < t.size(); ++r) {
      const auto a = banded_global_alignment(p, rotate(t, r), config);
      const bool better = a.within_k && (!want.within_k || a.cost < want.cost ||
                                         (a.cost == want.cost && a.differences < want.differences));
      if (better) want = a, want_r = r;
    }
    ASSERT_EQ(got.alignment.within_k, want.within_k) << p << " / " << t;
    if (!want.within_k) continue;
    ASSERT_EQ(got.alignment.cost, want.cost) << p << " / " << t;
    ASSERT_EQ(got.alignment.differences, want.differences);
    ASSERT_EQ(got.rotation, want_r);
    EXPECT_EQ(got.alignment.path, want.path);
  }
}

TEST(Cyclic, AlgorithmBEqualsEveryRotation) {
  std::mt19937 rng(2);
  for (int trial = 0; trial < 1500; ++trial) {
    const std::string t = random_fingerprint(rng, 2, 40, 4);
    const std::size_t k = std::uniform_int_distribution<std::size_t>(0, 5)(rng);
    const std::size_t len = std::uniform_int_distribution<std::size_t>(0, t.size() - std::min(t.size(), k))(rng);
    const std::size_t start = std::uniform_int_distribution<std::size_t>(0, t.size() - 1)(rng);
    std::string p = test_support::mutate(rng, rotate(t, start).substr(0, len), 0.3, 4);
    if (p.size() + k > t.size())
      p.resize(t.size() > k ? t.size() - k : 0);  // the doubled text covers every occurrence then
    const auto got = cyclic_k_differences(p, t, {k});
    const std::size_t m = t.size();
    std::vector<std::size_t> want(m + 1, static_cast<std::size_t>(-1));
    for (std::size_t r = 0; r < m; ++r) {
      for (const auto& o : k_differences(p, rotate(t, r), {k}).occurrences) {
        if (o.end == 0) continue;
        const std::size_t c = (o.end - 1 + r) % m + 1;
        want[c] = std::min(want[c], o.differences);
      }
    }
    std::vector<std::size_t> got_by_end(m + 1, static_cast<std::size_t>(-1));
    for (const auto& o : got.occurrences) {
      ASSERT_GE(o.end, 1U);
      ASSERT_LE(o.end, m);
      got_by_end[o.end] = o.differences;
    }
    if (p.empty()) continue;  // an empty pattern also matches before the first symbol
    ASSERT_EQ(got_by_end, want) << p << " in circular " << t << " k=" << k;
  }
}

TEST(Cyclic, AlgorithmCEqualsEveryRotation) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 800; ++trial) {
    const std::string t = random_fingerprint(rng, 0, 30, trial % 2 ? 2 : 8);
    const std::string p =
        t.empty()
            ? random_fingerprint(rng, 0, 5)
            : test_support::mutate(rng, rotate(t, std::uniform_int_distribution<std::size_t>(0, t.size() - 1)(rng)),
                                   0.4, trial % 2 ? 2 : 8);
    const auto got = cyclic_lcs_by_lis(p, t);
    std::size_t want = 0, want_r = 0;
    for (std::size_t r = 0; r < std::max<std::size_t>(t.size(), 1); ++r) {
      const std::size_t len = test_support::naive_lcs(p, rotate(t, r));
      if (len > want) want = len, want_r = r;
    }
    ASSERT_EQ(got.lcs.length, want) << p << " / " << t;
    EXPECT_EQ(got.rotation, want_r);
    const std::string rotated = rotate(t, got.rotation);
    for (const auto& [i, j] : got.lcs.pairs) EXPECT_EQ(p[i], rotated[j]);
  }
}

}  // namespace
}  // namespace seqtopo::strings
