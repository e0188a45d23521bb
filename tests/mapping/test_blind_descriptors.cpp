// MapConfig::drop_blind_descriptors: a descriptor that sees no revisit is left out of the fusion, one that adds
// evidence too weak to map alone stays, and nothing changes without a revisit.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "seqtopo/mapping/map_builder.hpp"

namespace seqtopo::mapping {
namespace {

// Symmetric noise, plus `strength` on a forward and a reverse revisit of 40 images each (0: none).
SimilarityMatrix descriptor(std::size_t n, unsigned seed, float strength) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0F, 1.0F);
  SimilarityMatrix s(n, n, 0.0F);
  for (auto& v : s.values) v = noise(rng);
  for (std::size_t k = 0; k < 40; ++k) s(100 + k, 10 + k) += strength, s(n - 1 - k, 40 + k) += strength;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < i; ++j) s(j, i) = s(i, j);
  }
  return s;
}

constexpr std::size_t kImages = 240;

TEST(BlindDescriptors, OneThatSeesNoRevisitIsLeftOutAndTheMapIsTheOthers) {
  const SimilarityMatrix sees = descriptor(kImages, 1, 3.0F), blind = descriptor(kImages, 2, 0.0F);
  const MapConfig config;
  const MapResult alone = build_map(sees, config);
  ASSERT_GE(alone.pruning.pairs.size(), 60U) << "the test needs the revisits found";
  const MapResult fused = build_map(std::vector<SimilarityMatrix>{sees, blind}, config);
  EXPECT_EQ(fused.decisions.blind_descriptors, std::vector<std::size_t>{1});
  EXPECT_EQ(fused.pruning.pairs, alone.pruning.pairs);
  EXPECT_EQ(fused.map.labels, alone.map.labels);
  EXPECT_EQ(fused.decisions.similarities, 2U);
  // In either order (formats/decision_notes.hpp says which, by name).
  const MapResult reversed = build_map(std::vector<SimilarityMatrix>{blind, sees}, config);
  EXPECT_EQ(reversed.decisions.blind_descriptors, std::vector<std::size_t>{0});
  // Without the check the noise is averaged in: fewer of the revisits' images are found.
  MapConfig keep = config;
  keep.drop_blind_descriptors = false;
  const MapResult diluted = build_map(std::vector<SimilarityMatrix>{sees, blind}, keep);
  EXPECT_TRUE(diluted.decisions.blind_descriptors.empty());
  EXPECT_NE(diluted.pruning.pairs, alone.pruning.pairs);
}

TEST(BlindDescriptors, OneTooWeakToMapAloneButScoringTheRevisitsStays) {
  const SimilarityMatrix sees = descriptor(kImages, 1, 3.0F), weak = descriptor(kImages, 3, 0.6F);
  const MapConfig config;
  ASSERT_TRUE(build_map(weak, config).pruning.pairs.empty()) << "the weak descriptor must map nothing alone";
  EXPECT_TRUE(build_map(std::vector<SimilarityMatrix>{sees, weak}, config).decisions.blind_descriptors.empty());
}

TEST(BlindDescriptors, WithoutARevisitNothingIsLeftOut) {
  const MapConfig config;
  for (unsigned seed = 10; seed < 14; ++seed) {
    const MapResult r = build_map(
        std::vector<SimilarityMatrix>{descriptor(kImages, seed, 0.0F), descriptor(kImages, seed + 100, 0.0F)}, config);
    EXPECT_TRUE(r.decisions.blind_descriptors.empty()) << "seed " << seed;
    EXPECT_TRUE(r.pruning.pairs.empty()) << "seed " << seed;
  }
}

}  // namespace
}  // namespace seqtopo::mapping
