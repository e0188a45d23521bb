// Graph construction on a figure-eight (mapping paper Fig. 1): start -> shared section -> loop ->
// shared section again (same direction) -> exit. Images 0..9 lead in, 10..19 are the shared section,
// 20..29 the loop, 30..39 the shared section again, 40..49 the exit.
#include <gtest/gtest.h>

#include "seqtopo/align/smith_waterman.hpp"
#include "seqtopo/mapping/map_builder.hpp"
#include "seqtopo/mapping/topological_map.hpp"

namespace seqtopo::mapping {
namespace {

constexpr std::size_t kImages = 50;

std::vector<std::pair<std::size_t, std::size_t>> revisit_pairs() {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t k = 0; k < 10; ++k) pairs.emplace_back(30 + k, 10 + k);
  return pairs;
}

void expect_figure_eight(const TopologicalMap& map) {
  const auto& labels = map.labels;
  for (std::size_t k = 0; k < 10; ++k) EXPECT_EQ(labels[30 + k], labels[10 + k]);
  EXPECT_EQ(map.places.size(), 40U);  // 50 images, 10 of them revisits
  const PlaceLabel merge = labels[10], branch = labels[19];
  // The shared section starts where the loop's end and the lead-in merge, and ends where the loop and
  // the exit branch off: both are junctions (degree 3), and nothing else is.
  EXPECT_EQ(map.junctions, (std::vector<PlaceLabel>{merge, branch}));
  ASSERT_EQ(map.segments.size(), 4U);
  // lead-in: from the start (a dead end) to the merge junction
  EXPECT_EQ(map.segments[0].places.front(), labels[0]);
  EXPECT_EQ(map.segments[0].places.back(), merge);
  EXPECT_EQ(map.segments[0].places.size(), 11U);
  // every segment starts and ends at a junction or a dead end
  for (const auto& s : map.segments) {
    for (PlaceLabel end : {s.places.front(), s.places.back()}) {
      const bool junction = end == merge || end == branch;
      const bool dead_end = end == labels[0] || end == labels[49];
      EXPECT_TRUE(junction || dead_end) << "segment ends at place " << end;
    }
  }
  // edges: 49 consecutive steps, 10 of them repeat an existing edge (the second pass of the shared
  // section repeats 9 edges, and 29 -> 30 is the new loop-closing edge): 49 - 9 = 40 distinct edges.
  EXPECT_EQ(map.edges.size(), 40U);
}

// The figure-eight's revisit as the engine would report it: images 30..40 revisit 10..20.
align::LocalAlignment revisit_alignment() {
  align::LocalAlignment a;
  a.score = 10;
  a.pairs = revisit_pairs();
  a.a_begin = 30;
  a.a_end = 40;
  a.b_begin = 10;
  a.b_end = 20;
  return a;
}

TEST(Topology, FigureEightFromHandBuiltAlignment) {
  const std::vector<align::LocalAlignment> alignments{revisit_alignment()};
  const auto pruning = prune_per_column(alignments);
  const auto labels = label_places(kImages, revisit_pairs());
  expect_figure_eight(build_topology(labels, alignments, pruning));
}

// The evidence of the figure-eight's two junctions, counted by hand: where each pass came from and went to.
TEST(Topology, JunctionEvidenceOfTheFigureEight) {
  const std::vector<align::LocalAlignment> alignments{revisit_alignment()};
  auto pruning = prune_per_column(alignments);
  for (auto& p : pruning.pairs) p.confidence = p.i == 30 ? 0.9 : 0.5;
  const auto labels = label_places(kImages, revisit_pairs());
  const TopologicalMap map = build_topology(labels, alignments, pruning);
  ASSERT_EQ(map.junction_evidence.size(), 2U);
  const auto& merge = map.junction_evidence[0];  // images 10 and 30: arrived from the lead-in and from the loop
  EXPECT_EQ(merge.place, labels[10]);
  EXPECT_EQ(merge.branches, (std::vector<PlaceLabel>{labels[9], labels[11], labels[29]}));
  ASSERT_EQ(merge.passes.size(), 2U);
  EXPECT_EQ(merge.passes[0].first_image, 10U);
  EXPECT_EQ(merge.passes[0].from, labels[9]);
  EXPECT_EQ(merge.passes[0].to, labels[11]);
  EXPECT_EQ(merge.passes[1].first_image, 30U);
  EXPECT_EQ(merge.passes[1].from, labels[29]);
  EXPECT_EQ(merge.passes[1].to, labels[31]);
  EXPECT_EQ(merge.images, (std::vector<std::size_t>{10, 30}));
  EXPECT_EQ(merge.alignments, std::vector<std::size_t>{0});
  EXPECT_EQ(merge.sessions, std::vector<std::size_t>{0});
  EXPECT_TRUE(merge.by_degree);
  EXPECT_TRUE(merge.by_alignment);
  EXPECT_DOUBLE_EQ(merge.confidence, 0.9);        // the best retained pair with an image here: (30, 10)
  const auto& branch = map.junction_evidence[1];  // images 19 and 39: leave to the loop and to the exit
  EXPECT_EQ(branch.place, labels[19]);
  EXPECT_EQ(branch.branches, (std::vector<PlaceLabel>{labels[18], labels[20], labels[40]}));
  EXPECT_EQ(branch.images, (std::vector<std::size_t>{19, 39}));
  EXPECT_DOUBLE_EQ(branch.confidence, 0.5);
}

TEST(Topology, FigureEightFromSimilarityMatrix) {
  // Similarity: consecutive images alike, the revisited section alike, everything else not.
  SimilarityMatrix s(kImages, kImages, -0.5F);
  for (std::size_t i = 0; i < kImages; ++i) {
    s(i, i) = 1.0F;
    if (i + 1 < kImages) s(i, i + 1) = s(i + 1, i) = 0.5F;
  }
  for (auto [i, j] : revisit_pairs()) s(i, j) = s(j, i) = 1.0F;
  MapConfig config;
  config.score.contrast_window = 0;  // align the hand-made S as it is
  config.search.min_separation = 5;
  config.search.cap = 5.0F;
  config.significance.threshold = 4.0F;
  const auto result = build_map(s, config);
  ASSERT_FALSE(result.alignments.empty());
  EXPECT_EQ(result.alignments.front().pairs, revisit_pairs());
  expect_figure_eight(result.map);
  // the kept alignment is the revisit; nothing else survives pruning
  std::size_t kept = 0;
  for (bool k : result.pruning.kept) kept += k ? 1 : 0;
  EXPECT_EQ(kept, 1U);
}

TEST(Topology, CorridorWalkedBackIsAReverseRevisitWithoutJunctionAtTheTurn) {
  // Out along a corridor (0..19), around a loop (20..39), back along the corridor (40..59 revisit
  // 19..0 in reverse). The loop's ends meet at image 19/40: a junction; the corridor's far end
  // (image 0 / 59) is where the walk started and stopped: not a junction.
  const std::size_t n = 60;
  SimilarityMatrix s(n, n, -0.5F);
  for (std::size_t i = 0; i < n; ++i) s(i, i) = 1.0F;
  for (std::size_t k = 0; k < 20; ++k) s(40 + k, 19 - k) = s(19 - k, 40 + k) = 1.0F;
  MapConfig config;
  config.score.contrast_window = 0;
  config.search.min_separation = 5;
  const auto result = build_map(s, config);
  ASSERT_FALSE(result.alignments.empty());
  EXPECT_EQ(result.alignments.front().direction, align::Direction::reverse);
  for (std::size_t k = 0; k < 20; ++k) EXPECT_EQ(result.map.labels[40 + k], result.map.labels[19 - k]);
  EXPECT_EQ(result.map.junctions, (std::vector<PlaceLabel>{result.map.labels[19]}));
}

TEST(Topology, FigureEightThroughContrastEnhancement) {
  // The same world with a noisy, offset similarity (some frames alike to everything): the default
  // pipeline enhances contrast first and still finds exactly the revisit.
  SimilarityMatrix s(kImages, kImages);
  std::uint32_t state = 7;
  for (std::size_t i = 0; i < kImages; ++i) {
    for (std::size_t j = 0; j <= i; ++j) {
      state = state * 1664525U + 1013904223U;
      const float noise = static_cast<float>(state >> 8) / static_cast<float>(1U << 24);
      s(i, j) = s(j, i) = 0.2F * noise + 0.3F * static_cast<float>((i % 7 == 0) + (j % 7 == 0));
    }
    s(i, i) = 1.5F;
  }
  for (auto [i, j] : revisit_pairs()) s(i, j) = s(j, i) = 1.5F;
  MapConfig config;
  ASSERT_GT(config.score.contrast_window, 0U) << "the default pipeline enhances contrast";
  config.search.min_separation = 5;
  // Uniform noise exceeds half a standard deviation in a third of the cells, which lets an alignment
  // grow into it by a frame or two at each end; rewarding only cells above one deviation keeps this
  // small world's revisit exact.
  config.score.contrast_offset = 1.0F;
  config.significance.threshold = 4.0F;
  const auto result = build_map(s, config);
  expect_figure_eight(result.map);
}

TEST(Topology, NoRevisitIsOneSegment) {
  const std::vector<PlaceLabel> labels{0, 1, 2, 3, 4};
  const auto map = build_topology(labels, {}, PruningResult{});
  EXPECT_TRUE(map.junctions.empty());
  ASSERT_EQ(map.segments.size(), 1U);
  EXPECT_EQ(map.segments[0].places, labels);
}

TEST(Topology, RejectsNonSquareSimilarity) {
  EXPECT_THROW(build_map(SimilarityMatrix(3, 4)), std::invalid_argument);
  EXPECT_THROW(build_map(SimilarityMatrix()), std::invalid_argument);
}

// One traversal through places 0..19; others (sessions of their own) arrive from places of their own and join
// it at places 8, 9 and 10 (a knot of branching places, one junction on the ground) and at place 15.
struct Knot {
  std::vector<PlaceLabel> labels;
  std::vector<std::size_t> session_starts;
};
Knot knot() {
  Knot k;
  const auto drive = [&](int from, int to) {
    for (int p = from; from <= to ? p <= to : p >= to; p += from <= to ? 1 : -1) k.labels.push_back(p);
  };
  const auto session = [&] { k.session_starts.push_back(k.labels.size()); };
  drive(0, 19);
  session(), drive(20, 24), drive(8, 5);    // joins at 8 towards the start
  session(), drive(30, 34), drive(10, 12);  // joins at 10 towards the end
  session(), drive(40, 44), drive(9, 9);    // ends at 9: place 9 gets a third neighbour
  session(), drive(50, 54), drive(15, 13);  // joins at 15
  return k;
}

TEST(Topology, BranchingPlacesCloseTogetherAreOneJunction) {
  const auto [labels, starts] = knot();
  TopologyConfig config;
  config.session_starts = starts;
  const auto apart = build_topology(labels, {}, {}, config);
  EXPECT_EQ(apart.junctions, (std::vector<PlaceLabel>{8, 9, 10, 15}));
  config.junction_region = 3;
  const auto knot = build_topology(labels, {}, {}, config);
  // 8, 9 and 10 are one junction at its centre 9; 15 is 5 edges away and stays one of its own.
  EXPECT_EQ(knot.junctions, (std::vector<PlaceLabel>{9, 15}));
  ASSERT_EQ(knot.junction_evidence.size(), 2U);
  const auto& j = knot.junction_evidence[0];
  EXPECT_EQ(j.place, 9);
  EXPECT_EQ(j.region, (std::vector<PlaceLabel>{8, 9, 10}));
  EXPECT_EQ(j.branches, (std::vector<PlaceLabel>{7, 11, 24, 34, 44}));  // out of the knot
  EXPECT_TRUE(j.by_degree);
  // The first traversal crosses the knot once (images 8..10), the others enter it once each.
  ASSERT_EQ(j.passes.size(), 4U);
  EXPECT_EQ(j.passes[0].first_image, 8U);
  EXPECT_EQ(j.passes[0].last_image, 10U);
  EXPECT_EQ(j.passes[0].from, 7);
  EXPECT_EQ(j.passes[0].to, 11);
  EXPECT_EQ(knot.junction_evidence[1].region, (std::vector<PlaceLabel>{15}));
  // Single linkage: within 1 edge, 8 - 9 - 10 still chain into one junction; a region of 0 keeps them apart.
  config.junction_region = 1;
  EXPECT_EQ(build_topology(labels, {}, {}, config).junctions, (std::vector<PlaceLabel>{9, 15}));
  // The segments do not depend on how junctions are grouped.
  EXPECT_EQ(knot.segments.size(), apart.segments.size());
}

}  // namespace
}  // namespace seqtopo::mapping
