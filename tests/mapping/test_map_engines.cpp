// The map's two alignment engines: on scores the fast engine represents exactly (multiples of 1/512 with
// the default cap), they give the same alignments, places and junctions.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "seqtopo/mapping/map_builder.hpp"

namespace seqtopo::mapping {
namespace {

TEST(MapEngines, FastEqualsExactOnQuantizedScores) {
  for (unsigned seed = 1; seed <= 6; ++seed) {
    std::mt19937 rng(seed);
    const std::size_t n = 150 + 25 * seed;
    std::normal_distribution<float> noise(-0.4F, 0.5F);
    SimilarityMatrix s(n, n, 0.0F);
    for (auto& v : s.values) v = noise(rng);
    // a forward and a reverse revisit
    for (std::size_t k = 0; k < 40; ++k) s(100 + k, 10 + k) += 1.5F, s(n - 1 - k, 40 + k) += 1.5F;
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < i; ++j) s(j, i) = s(i, j);
    }
    for (auto& v : s.values) v = std::round(v * 512.0F) / 512.0F;
    // With the significance statistics (their threshold and cap on a 1/64 grid) and with a fixed threshold.
    for (bool statistics : {true, false}) {
      MapConfig config;
      config.score.contrast_window = 0;  // align S itself, so the quantized values reach the engines unchanged
      config.unit = align::Unit::frames;
      if (!statistics) {
        config.significance.max_e_value.reset();
        config.significance.threshold = 6;
      }
      const MapResult exact = build_map(s, config);
      config.engine = MapConfig::Engine::fast;
      for (unsigned threads : {1U, 2U}) {
        config.threads = threads;
        const MapResult fast = build_map(s, config);
        ASSERT_FALSE(exact.alignments.empty());
        EXPECT_EQ(fast.alignments, exact.alignments) << "seed " << seed << ", threads " << threads;
        EXPECT_EQ(fast.map.labels, exact.map.labels);
        EXPECT_EQ(fast.map.junctions, exact.map.junctions);
        if (statistics) {
          EXPECT_EQ(fast.e_values, exact.e_values);
          EXPECT_TRUE(exact.decisions.statistics.valid());
        }
      }
    }
  }
}

}  // namespace
}  // namespace seqtopo::mapping
