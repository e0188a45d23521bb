// Algorithm A against full-table dynamic programming and against edlib's global mode.
#include <edlib.h>
#include <gtest/gtest.h>

#include <cstdlib>

#include "naive_string_dp.hpp"
#include "seqtopo/strings/banded_global_alignment.hpp"

namespace seqtopo::strings {
namespace {

using test_support::naive_global;
using test_support::random_fingerprint;

// The diagonals an alignment with <= k differences can use, found by testing every diagonal.
std::pair<std::int64_t, std::int64_t> band_by_scan(std::size_t n, std::size_t m, std::size_t k) {
  const auto delta = static_cast<std::int64_t>(m) - static_cast<std::int64_t>(n);
  std::int64_t lo = 1, hi = 0;
  for (std::int64_t d = -static_cast<std::int64_t>(n); d <= static_cast<std::int64_t>(m); ++d) {
    if (std::abs(d) + std::abs(d - delta) <= static_cast<std::int64_t>(k)) {
      if (lo > hi) lo = d;
      hi = d;
    }
  }
  return {lo, hi};
}

// Re-scores an edit path and checks it spells P and T.
double path_cost(std::string_view p, std::string_view t, const std::string& path, const EditCosts& c,
                 std::size_t* diffs) {
  std::size_t i = 0, j = 0;
  double cost = 0.0;
  *diffs = 0;
  for (char op : path) {
    if (op == '=' || op == 'X') {
      EXPECT_EQ(op == '=', p[i] == t[j]);
      cost += c.substitution(p[i], t[j]);
      *diffs += op == 'X';
      ++i, ++j;
    } else if (op == 'D') {
      cost += c.deletion, ++i, ++*diffs;
    } else {
      EXPECT_EQ(op, 'I');
      cost += c.insertion, ++j, ++*diffs;
    }
  }
  EXPECT_EQ(i, p.size());
  EXPECT_EQ(j, t.size());
  return cost;
}

TEST(BandedGlobalAlignment, WorkedExample) {
  GlobalAlignmentConfig config;
  config.k = 1;
  config.want_path = true;
  const auto a = banded_global_alignment("vAvB", "vAvvB", config);
  EXPECT_TRUE(a.within_k);
  EXPECT_DOUBLE_EQ(a.cost, 1.0);
  EXPECT_EQ(a.differences, 1U);
  EXPECT_EQ(a.path, "==I==");  // the traceback prefers the diagonal from the end
  config.k = 0;
  EXPECT_FALSE(banded_global_alignment("vAvB", "vAvvB", config).within_k);
  EXPECT_TRUE(banded_global_alignment("", "", config).within_k);
}

TEST(BandedGlobalAlignment, ColourDifferenceIsCheaperThanDiscordance) {
  GlobalAlignmentConfig config;
  config.costs = preset_costs("A2-rooms");
  EXPECT_DOUBLE_EQ(banded_global_alignment("vAv", "vBv", config).cost, 0.75);
  EXPECT_DOUBLE_EQ(banded_global_alignment("vAv", "vvv", config).cost, 1.0);
  config.costs = preset_costs("A2-ground-floor");  // coincidences are rewarded
  EXPECT_DOUBLE_EQ(banded_global_alignment("vAv", "vAv", config).cost, -0.45);
}

TEST(BandedGlobalAlignment, RejectsInvalidCosts) {
  GlobalAlignmentConfig config;
  config.costs.deletion = -1.0;
  EXPECT_THROW(banded_global_alignment("a", "b", config), std::invalid_argument);
  config.costs = {};
  config.costs.colour_distance = ColourDistanceTable{};
  (*config.costs.colour_distance)[0][1] = 0.5;  // not symmetric
  EXPECT_THROW(banded_global_alignment("a", "b", config), std::invalid_argument);
  EXPECT_THROW(preset_costs("A3"), std::invalid_argument);
}

TEST(BandedGlobalAlignment, MatchesFullTableOnRandomStrings) {
  std::mt19937 rng(20240611);
  const std::vector<EditCosts> tables = {preset_costs("A1"), preset_costs("A2-rooms"), preset_costs("A2-ground-floor"),
                                         preset_costs("A2-white-hall"), preset_costs("A2-global")};
  std::size_t within = 0, beyond = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const std::string p = random_fingerprint(rng, 0, 30);
    const std::string t =
        std::bernoulli_distribution(0.5)(rng) ? test_support::mutate(rng, p, 0.3) : random_fingerprint(rng, 0, 30);
    GlobalAlignmentConfig config;
    config.costs = tables[static_cast<std::size_t>(trial) % tables.size()];
    config.want_path = true;
    const bool limited = trial % 3 != 0;
    if (limited) config.k = std::uniform_int_distribution<std::size_t>(0, 20)(rng);
    const auto got = banded_global_alignment(p, t, config);
    std::pair<double, std::size_t> want;
    if (limited) {
      const auto [lo, hi] = band_by_scan(p.size(), t.size(), config.k);
      want = naive_global(p, t, config.costs, lo, hi);
    } else {
      want = naive_global(p, t, config.costs);
    }
    const bool want_within =
        want.first != std::numeric_limits<double>::infinity() && (!limited || want.second <= config.k);
    ASSERT_EQ(got.within_k, want_within) << p << " / " << t << " k=" << config.k;
    (got.within_k ? within : beyond)++;
    if (!got.within_k) continue;
    ASSERT_EQ(got.cost, want.first) << p << " / " << t;  // same recurrence, same sums: bit-identical
    ASSERT_EQ(got.differences, want.second);
    std::size_t diffs = 0;
    EXPECT_NEAR(path_cost(p, t, got.path, config.costs, &diffs), got.cost, 1e-9);
    EXPECT_EQ(diffs, got.differences);
  }
  EXPECT_GT(within, 500U);  // both outcomes were exercised
  EXPECT_GT(beyond, 300U);
}

TEST(BandedGlobalAlignment, UnitCostsAgreeWithEdlibGlobalMode) {
  std::mt19937 rng(77);
  for (int trial = 0; trial < 3000; ++trial) {
    const std::string p = random_fingerprint(rng, 1, 60, 15);
    const std::string t = std::bernoulli_distribution(0.6)(rng) ? test_support::mutate(rng, p, 0.25, 15)
                                                                : random_fingerprint(rng, 1, 60, 15);
    if (t.empty()) continue;
    const int k = std::uniform_int_distribution<int>(0, 30)(rng);
    const EdlibAlignResult ref = edlibAlign(p.data(), static_cast<int>(p.size()), t.data(), static_cast<int>(t.size()),
                                            edlibNewAlignConfig(k, EDLIB_MODE_NW, EDLIB_TASK_DISTANCE, nullptr, 0));
    ASSERT_EQ(ref.status, EDLIB_STATUS_OK);
    GlobalAlignmentConfig config;
    config.k = static_cast<std::size_t>(k);
    const auto got = banded_global_alignment(p, t, config);
    ASSERT_EQ(got.within_k, ref.editDistance >= 0) << p << " / " << t << " k=" << k;
    if (got.within_k) {
      EXPECT_EQ(got.cost, static_cast<double>(ref.editDistance));
      EXPECT_EQ(got.differences, static_cast<std::size_t>(ref.editDistance));
    }
    // With no limit the result is the plain edit distance.
    EXPECT_EQ(banded_global_alignment(p, t).cost, static_cast<double>(test_support::naive_edit_distance(p, t)));
    edlibFreeAlignResult(ref);
  }
}

}  // namespace
}  // namespace seqtopo::strings
