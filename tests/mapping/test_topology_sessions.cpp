// Session boundaries in the topology (TopologyConfig::session_starts): no edge joins one session's last image
// to the next one's first, and neither counts as the other's neighbour for the junction test.
#include <gtest/gtest.h>

#include "seqtopo/mapping/topological_map.hpp"

namespace seqtopo::mapping {
namespace {

TEST(TopologySessions, NoEdgeAcrossASessionBoundary) {
  // Two sessions of the same route, places 0..4 each: images 0..4 then 5..9 with the same labels.
  const std::vector<PlaceLabel> labels{0, 1, 2, 3, 4, 0, 1, 2, 3, 4};
  const PruningResult pruning;  // no alignment needed for the edges
  const TopologicalMap one = build_topology(labels, {}, pruning);
  // As one sequence, image 4 (place 4) is followed by image 5 (place 0): a loop 0-1-2-3-4-0.
  EXPECT_EQ(one.edges, (std::vector<std::pair<PlaceLabel, PlaceLabel>>{{0, 1}, {0, 4}, {1, 2}, {2, 3}, {3, 4}}));
  TopologyConfig config;
  config.session_starts = {5};
  const TopologicalMap two = build_topology(labels, {}, pruning, config);
  EXPECT_EQ(two.edges, (std::vector<std::pair<PlaceLabel, PlaceLabel>>{{0, 1}, {1, 2}, {2, 3}, {3, 4}}));
  ASSERT_EQ(two.segments.size(), 1U);  // one path from place 0 to place 4, not a loop
  EXPECT_EQ(two.segments[0].places, (std::vector<PlaceLabel>{0, 1, 2, 3, 4}));
}

TEST(TopologySessions, BoundaryIsNoNeighbourForJunctions) {
  // Session 1: places 0 1 2 3 (images 0..3); session 2: places 1 2 3 9 (images 4..7), aligned with images 1..3.
  const std::vector<PlaceLabel> labels{0, 1, 2, 3, 1, 2, 3, 9};
  align::LocalAlignment a;
  a.direction = align::Direction::forward;
  a.pairs = {{4, 1}, {5, 2}, {6, 3}};
  PruningResult pruning;
  pruning.kept = {true};
  for (const auto& [i, j] : a.pairs) pruning.pairs.push_back({i, j, 0, 1.0F});
  // As one sequence: image 3 (place 3) leads to image 4 (place 1), so places 1 and 3 have three neighbours,
  // and the alignment arrives from different places (image 3 vs image 0) and leaves to different ones (image 7
  // vs image 4).
  EXPECT_EQ(build_topology(labels, {a}, pruning).junctions, (std::vector<PlaceLabel>{1, 3}));
  // With session 2 starting at image 4 the path does not pass from 3 to 1, and image 4 has no predecessor nor
  // image 3 a successor for the alignment's ends: no junction.
  TopologyConfig config;
  config.session_starts = {4};
  const auto split = build_topology(labels, {a}, pruning, config);
  EXPECT_TRUE(split.junctions.empty());
  EXPECT_EQ(split.edges, (std::vector<std::pair<PlaceLabel, PlaceLabel>>{{0, 1}, {1, 2}, {2, 3}, {3, 9}}));
}

}  // namespace
}  // namespace seqtopo::mapping
