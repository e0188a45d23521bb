// RunningMedian against std::nth_element on the values so far, after every value: random values, ties, runs up
// and down, and clear().
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "seqtopo/core/running_median.hpp"

namespace seqtopo {
namespace {

double upper_median(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

TEST(RunningMedian, IsTheUpperMedianOfTheValuesSoFar) {
  std::mt19937 rng(9);
  std::uniform_int_distribution<int> small(0, 5);  // many ties
  std::normal_distribution<double> g(0.0, 3.0);
  for (int kind = 0; kind < 4; ++kind) {
    RunningMedian m;
    EXPECT_EQ(m.median(), 0.0);
    std::vector<double> seen;
    for (int k = 0; k < 300; ++k) {
      const double v = kind == 0 ? g(rng) : kind == 1 ? small(rng) : kind == 2 ? k : 300.0 - k;
      m.add(v);
      seen.push_back(v);
      ASSERT_EQ(m.size(), seen.size());
      ASSERT_EQ(m.median(), upper_median(seen)) << kind << ": " << k;
    }
    m.clear();
    EXPECT_EQ(m.size(), 0U);
    m.add(4.0);
    EXPECT_EQ(m.median(), 4.0);
  }
}

}  // namespace
}  // namespace seqtopo
