// `--preset paper` is the mapping paper's pipeline (sections IV-A to IV-D): joint histograms compared by chi2,
// S = 1 - kappa D aligned as it is with a fixed threshold, per-column pruning and transitive labels, the map read
// from those labels; odometry only draws the picture (IV-D: "merely an aid for a human"), so it never changes the map.
#include <gtest/gtest.h>

#include "seqtopo/mapping/map_builder.hpp"
#include "seqtopo/pipeline/presets.hpp"

namespace seqtopo::pipeline {
namespace {

TEST(PaperPreset, IsThePapersPipeline) {
  const MapSettings s = map_preset("paper");
  EXPECT_EQ(s.descriptors, std::vector<Descriptor>{Descriptor::joint_histogram});
  EXPECT_EQ(s.similarity.distance, Distance::chi2);
  EXPECT_EQ(s.map.score.contrast_window, 0U);  // S = 1 - kappa D, no enhancement
  EXPECT_FALSE(s.map.significance.max_e_value.has_value());
  EXPECT_EQ(s.map.unit, align::Unit::frames);
  EXPECT_EQ(s.map.labels.method, mapping::LabelSettings::Method::pruned_transitive);
  EXPECT_EQ(s.map.labels.pruning.rank, mapping::PruningConfig::Rank::length_then_score);
  EXPECT_FALSE(s.map.odometry.gate.has_value());
  EXPECT_FALSE(s.map.graph.clean);
  // and the default is not that pipeline
  const MapSettings d = map_preset("default");
  EXPECT_TRUE(d.map.odometry.gate.has_value());
  EXPECT_TRUE(d.map.graph.clean);
}

// A corridor walked out and back (81 images), with a true reverse revisit and a forward copy 20 images apart that
// odometry contradicts. The paper's map is the same with and without the odometry; the same settings with the
// odometry gate switched on drop the copy (so the odometry given would change the map if it were used).
TEST(PaperPreset, OdometryNeverChangesTheMap) {
  std::vector<Pose2> odometry;
  for (int k = 0; k <= 80; ++k) odometry.push_back({k <= 40 ? 0.5 * k : 0.5 * (80 - k), 0.01 * k, 0});
  const std::size_t n = odometry.size();
  SimilarityMatrix s(n, n, 0.0F);
  for (std::size_t d = 5; d < 30; ++d) s(40 + d, 40 - d) = s(40 - d, 40 + d) = 1.0F;
  for (std::size_t i = 20; i < 40; ++i) s(i, i - 20) = s(i - 20, i) = 1.0F;
  const mapping::MapConfig paper = map_preset("paper").map;
  const mapping::MapResult without = mapping::build_map(s, paper);
  const mapping::MapResult with = mapping::build_map(s, paper, odometry);
  EXPECT_TRUE(with.rejected.empty());
  EXPECT_EQ(with.alignments, without.alignments);
  EXPECT_EQ(with.pruning.pairs, without.pruning.pairs);
  EXPECT_EQ(with.map.labels, without.map.labels);
  EXPECT_EQ(with.map.edges, without.map.edges);
  EXPECT_EQ(with.map.junctions, without.map.junctions);
  EXPECT_EQ(with.map.labels[30], with.map.labels[10]);  // the copy the gate would have dropped is in the map

  mapping::MapConfig gated = paper;
  gated.odometry.gate = mapping::OdometryGate{};
  const mapping::MapResult vetoed = mapping::build_map(s, gated, odometry);
  ASSERT_EQ(vetoed.rejected.size(), 1U);
  EXPECT_NE(vetoed.map.labels[30], vetoed.map.labels[10]);
}

}  // namespace
}  // namespace seqtopo::pipeline

namespace seqtopo::pipeline {
namespace {

TEST(PanoramaDefaults, RecognisesPanoramasByTheirAspect) {
  EXPECT_TRUE(looks_panoramic(360, 60));    // seqtopo simulate
  EXPECT_TRUE(looks_panoramic(120, 40));    // exactly 3:1
  EXPECT_FALSE(looks_panoramic(119, 40));   // just under
  EXPECT_FALSE(looks_panoramic(512, 384));  // the bundled corridor (4:3)
  EXPECT_FALSE(looks_panoramic(64, 32));    // Nordland (2:1)
  EXPECT_FALSE(looks_panoramic(0, 0));
  EXPECT_FALSE(looks_panoramic(-360, -60));
}

TEST(PanoramaDefaults, ReplacesThePatchThumbnail) {
  using D = Descriptor;
  EXPECT_EQ(panorama_descriptors({D::joint_histogram, D::patch}), (std::vector<D>{D::joint_histogram, D::panorama}));
  EXPECT_EQ(panorama_descriptors({D::joint_histogram}), (std::vector<D>{D::joint_histogram, D::panorama}));
  EXPECT_EQ(panorama_descriptors({D::panorama, D::patch}), (std::vector<D>{D::panorama, D::patch}));
  EXPECT_EQ(panorama_descriptors(map_preset("default").descriptors), (std::vector<D>{D::joint_histogram, D::panorama}));
  EXPECT_TRUE(map_preset("default").detect_panoramas);
  EXPECT_FALSE(map_preset("paper").detect_panoramas);
}

}  // namespace
}  // namespace seqtopo::pipeline
