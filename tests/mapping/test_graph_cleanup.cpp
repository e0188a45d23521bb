// The place graph's clean-up (graph_cleanup.hpp) on hand-built labellings, each with the exact graph it
// must give: a bubble, a tip, an overhang, a path seen three times, a reverse traversal with its U-turn, a
// half-speed traversal; and what it must leave alone (a long lead-in, a real second route).
#include <gtest/gtest.h>

#include <numeric>

#include "seqtopo/mapping/graph_cleanup.hpp"
#include "seqtopo/mapping/topological_map.hpp"

namespace seqtopo::mapping {
namespace {

using Pairs = std::vector<std::pair<std::size_t, std::size_t>>;

struct Case {
  std::vector<PlaceLabel> labels;
  std::vector<align::LocalAlignment> alignments;
  PruningResult pruning;
  std::vector<std::size_t> session_starts;
};

// One alignment per list of pairs, every pair accepted.
Case make_case(std::vector<PlaceLabel> labels, const std::vector<std::pair<align::Direction, Pairs>>& alignments,
               std::vector<std::size_t> session_starts = {}) {
  Case c{std::move(labels), {}, {}, std::move(session_starts)};
  for (std::size_t k = 0; k < alignments.size(); ++k) {
    align::LocalAlignment a;
    a.direction = alignments[k].first;
    a.pairs = alignments[k].second;
    a.score = 10;
    c.alignments.push_back(a);
    c.pruning.kept.push_back(true);
    c.pruning.retained_count.push_back(a.pairs.size());
    for (auto [i, j] : a.pairs) c.pruning.pairs.push_back({i, j, k, 10});
  }
  return c;
}

GraphCleanupConfig config_of(const Case& c) {
  GraphCleanupConfig config;
  config.min_separation = 5;
  config.session_starts = c.session_starts;
  return config;
}

TopologicalMap cleaned_map(const Case& c, const GraphCleanupConfig& config) {
  const GraphCleanup cleanup = clean_graph(c.labels, c.alignments, c.pruning, config);
  TopologyConfig topology;
  topology.u_turn_separation = 3;
  topology.session_starts = c.session_starts;
  topology.reduce_transitive = true;
  return build_topology(cleanup.labels, c.alignments, c.pruning, topology);
}

using Edges = std::vector<std::pair<PlaceLabel, PlaceLabel>>;

Edges cycle(PlaceLabel n) {
  Edges e;
  for (PlaceLabel p = 0; p + 1 < n; ++p) e.emplace_back(p, p + 1);
  e.emplace_back(0, n - 1);
  std::sort(e.begin(), e.end());
  return e;
}

Edges path(PlaceLabel n) {
  Edges e;
  for (PlaceLabel p = 0; p + 1 < n; ++p) e.emplace_back(p, p + 1);
  return e;
}

// A loop of 20 places driven round one and a half times (images 20..29 revisit 0..9); image 25 of the
// second pass was left in a place of its own, a bubble 4 - X - 6 beside 4 - 5 - 6 that the alignment spans.
TEST(GraphCleanup, PopsABubbleTheAlignmentSpans) {
  std::vector<PlaceLabel> labels(30);
  std::iota(labels.begin(), labels.begin() + 20, 0);
  for (std::size_t k = 20; k < 30; ++k) labels[k] = static_cast<PlaceLabel>(k - 20);
  labels[25] = 20;
  Pairs pairs;
  for (std::size_t k = 20; k < 30; ++k) {
    if (k != 25) pairs.emplace_back(k, k - 20);
  }
  const Case c = make_case(labels, {{align::Direction::forward, pairs}});
  const TopologicalMap before = build_topology(c.labels, c.alignments, c.pruning, {});
  EXPECT_EQ(before.places.size(), 21U);
  EXPECT_EQ(before.edges.size(), 22U);  // the bubble: two independent cycles

  const GraphCleanup cleanup = clean_graph(c.labels, c.alignments, c.pruning, config_of(c));
  EXPECT_EQ(cleanup.popped_images, 1U);
  EXPECT_EQ(cleanup.labels[25], cleanup.labels[5]);
  const TopologicalMap map = cleaned_map(c, config_of(c));
  EXPECT_EQ(map.places.size(), 20U);
  EXPECT_EQ(map.edges, cycle(20));
  EXPECT_TRUE(map.junctions.empty());
}

// The same bubble with no alignment across it, and both routes seen once: by time, the later pass's detour is
// merged into the first visit's places; asked for an alignment's evidence, it stays.
TEST(GraphCleanup, BubbleWithoutAnAlignmentAcrossIt) {
  std::vector<PlaceLabel> labels(30);
  std::iota(labels.begin(), labels.begin() + 20, 0);
  for (std::size_t k = 20; k < 30; ++k) labels[k] = static_cast<PlaceLabel>(k - 20);
  labels[25] = 20;
  const Case c = make_case(labels, {{align::Direction::forward, {{21, 1}, {22, 2}, {23, 3}}},
                                    {align::Direction::forward, {{27, 7}, {28, 8}, {29, 9}}}});
  const GraphCleanup by_time = clean_graph(c.labels, c.alignments, c.pruning, config_of(c));
  EXPECT_EQ(by_time.popped_images, 1U);
  EXPECT_EQ(by_time.labels[25], by_time.labels[5]);
  EXPECT_EQ(by_time.labels[5], 5);  // the first visit keeps its place
  GraphCleanupConfig strict = config_of(c);
  strict.pop_ties_by_time = false;
  EXPECT_EQ(clean_graph(c.labels, c.alignments, c.pruning, strict).popped_images, 0U);
  EXPECT_EQ(cleaned_map(c, strict).places.size(), 21U);
}

// A detour longer than the shortest revisit is a route of its own: two passes between places 4 and 9, one
// through 5..8 and one through four places of its own.
TEST(GraphCleanup, KeepsALongDetour) {
  std::vector<PlaceLabel> labels(30);
  std::iota(labels.begin(), labels.begin() + 20, 0);
  for (std::size_t k = 20; k < 30; ++k) labels[k] = static_cast<PlaceLabel>(k - 20);
  for (std::size_t k = 25; k < 29; ++k) labels[k] = static_cast<PlaceLabel>(k - 5);  // places 20..23
  Pairs pairs;
  for (std::size_t k = 20; k < 30; ++k) {
    if (k < 25 || k > 28) pairs.emplace_back(k, k - 20);
  }
  const Case c = make_case(labels, {{align::Direction::forward, pairs}});
  const GraphCleanup cleanup = clean_graph(c.labels, c.alignments, c.pruning, config_of(c));
  EXPECT_EQ(cleanup.popped_images, 0U);
  EXPECT_EQ(cleaned_map(c, config_of(c)).places.size(), 24U);
}

// The bundled corridor's shape: image 0, before the loop, was never aligned; 13..24 revisit 1..12.
Case corridor_case() {
  std::vector<PlaceLabel> labels(25);
  std::iota(labels.begin(), labels.begin() + 13, 0);
  for (std::size_t k = 13; k < 25; ++k) labels[k] = static_cast<PlaceLabel>(k - 12);
  Pairs pairs;
  for (std::size_t k = 13; k < 25; ++k) pairs.emplace_back(k, k - 12);
  return make_case(labels, {{align::Direction::forward, pairs}});
}

TEST(GraphCleanup, ExtendsAnOverhangToTheSessionsStart) {
  const Case c = corridor_case();
  EXPECT_EQ(build_topology(c.labels, c.alignments, c.pruning, {}).junctions, std::vector<PlaceLabel>{1});
  const GraphCleanup cleanup = clean_graph(c.labels, c.alignments, c.pruning, config_of(c));
  EXPECT_EQ(cleanup.extended_images, 1U);
  EXPECT_EQ(cleanup.labels[0], cleanup.labels[12]);  // the alignment continued: (12, 0)
  const TopologicalMap map = cleaned_map(c, config_of(c));
  EXPECT_EQ(map.places.size(), 12U);
  EXPECT_EQ(map.edges, cycle(12));
  EXPECT_TRUE(map.junctions.empty());
}

TEST(GraphCleanup, ClipsAShortTip) {
  const Case c = corridor_case();
  GraphCleanupConfig config = config_of(c);
  config.hang_fraction = 0;  // no overhang: the tip rule alone
  const GraphCleanup cleanup = clean_graph(c.labels, c.alignments, c.pruning, config);
  EXPECT_EQ(cleanup.extended_images, 0U);
  EXPECT_EQ(cleanup.clipped_images, 1U);
  EXPECT_EQ(cleanup.labels[0], cleanup.labels[1]);  // the place it hangs from
  const TopologicalMap map = cleaned_map(c, config);
  EXPECT_EQ(map.places.size(), 12U);
  EXPECT_EQ(map.edges, cycle(12));
  EXPECT_TRUE(map.junctions.empty());
}

// A lead-in of 10 images (the mapping paper's Fig. 1) is longer than any tip: it stays, and so do its junctions.
TEST(GraphCleanup, KeepsALongLeadIn) {
  std::vector<PlaceLabel> labels(40);
  std::iota(labels.begin(), labels.begin() + 30, 0);
  for (std::size_t k = 30; k < 40; ++k) labels[k] = static_cast<PlaceLabel>(k - 20);
  Pairs pairs;
  for (std::size_t k = 30; k < 40; ++k) pairs.emplace_back(k, k - 20);
  const Case c = make_case(labels, {{align::Direction::forward, pairs}});
  const GraphCleanup cleanup = clean_graph(c.labels, c.alignments, c.pruning, config_of(c));
  EXPECT_EQ(cleanup.labels, c.labels);
  EXPECT_EQ(cleaned_map(c, config_of(c)).junctions, std::vector<PlaceLabel>{10});
}

// One path of 10 places recorded in three sessions; each session's first image was left unaligned.
TEST(GraphCleanup, PathSeenThreeTimes) {
  std::vector<PlaceLabel> labels(30);
  for (std::size_t k = 0; k < 30; ++k) labels[k] = static_cast<PlaceLabel>(k % 10);
  labels[10] = 10;
  labels[20] = 11;
  Pairs a, b;
  for (std::size_t k = 1; k < 10; ++k) {
    a.emplace_back(10 + k, k);
    b.emplace_back(20 + k, 10 + k);
  }
  const Case c = make_case(labels, {{align::Direction::forward, a}, {align::Direction::forward, b}}, {10, 20});
  TopologyConfig sessions;
  sessions.session_starts = c.session_starts;
  const TopologicalMap before = build_topology(c.labels, c.alignments, c.pruning, sessions);
  EXPECT_EQ(before.junctions, std::vector<PlaceLabel>{1});
  const TopologicalMap map = cleaned_map(c, config_of(c));
  EXPECT_EQ(map.places.size(), 10U);
  EXPECT_EQ(map.edges, path(10));
  EXPECT_TRUE(map.junctions.empty());
  for (std::size_t k = 0; k < 10; ++k) {
    EXPECT_EQ(map.labels[k], map.labels[k + 10]);
    EXPECT_EQ(map.labels[k], map.labels[k + 20]);
  }
}

// Out along a corridor of 10 places and back (image 10 + k is image 9 - k): the reverse alignment stops one
// image short of the U-turn and of the sequence's end.
TEST(GraphCleanup, ReverseTraversalWithItsUTurn) {
  std::vector<PlaceLabel> labels(20);
  std::iota(labels.begin(), labels.begin() + 10, 0);
  labels[10] = 10;
  labels[19] = 11;
  Pairs pairs;
  for (std::size_t k = 1; k <= 8; ++k) {
    labels[10 + k] = static_cast<PlaceLabel>(9 - k);
    pairs.emplace_back(10 + k, 9 - k);
  }
  const Case c = make_case(labels, {{align::Direction::reverse, pairs}});
  const TopologicalMap before = build_topology(c.labels, c.alignments, c.pruning, {});
  EXPECT_EQ(before.places.size(), 12U);
  const TopologicalMap map = cleaned_map(c, config_of(c));
  EXPECT_EQ(map.places.size(), 10U);
  EXPECT_EQ(map.edges, path(10));
  EXPECT_TRUE(map.junctions.empty());
  EXPECT_EQ(map.labels[19], map.labels[0]);  // the overhang at the end
  EXPECT_EQ(map.labels[10], map.labels[9]);  // the hairpin at the U-turn
}

// A loop of 20 places, then its first 10 places again at half speed: images 20 + 2k are aligned with k, the
// images between them were left in places of their own (bubbles k - X - k+1 beside the edge k - k+1).
TEST(GraphCleanup, HalfSpeedTraversal) {
  std::vector<PlaceLabel> labels(39);
  std::iota(labels.begin(), labels.begin() + 20, 0);
  Pairs pairs;
  PlaceLabel extra = 20;
  for (std::size_t k = 0; k < 10; ++k) {
    labels[20 + 2 * k] = static_cast<PlaceLabel>(k);
    pairs.emplace_back(20 + 2 * k, k);
    if (21 + 2 * k < labels.size()) labels[21 + 2 * k] = extra++;
  }
  const Case c = make_case(labels, {{align::Direction::forward, pairs}});
  EXPECT_EQ(build_topology(c.labels, c.alignments, c.pruning, {}).places.size(), 29U);
  const GraphCleanup cleanup = clean_graph(c.labels, c.alignments, c.pruning, config_of(c));
  EXPECT_EQ(cleanup.popped_images, 9U);
  for (std::size_t k = 0; k < 9; ++k) EXPECT_EQ(cleanup.labels[21 + 2 * k], cleanup.labels[k]) << k;
  const TopologicalMap map = cleaned_map(c, config_of(c));
  EXPECT_EQ(map.places.size(), 20U);
  EXPECT_EQ(map.edges, cycle(20));
  EXPECT_TRUE(map.junctions.empty());
}

// A pass that went past a place between two images (twice as fast) leaves the edge p - q beside p - x - q, each
// of whose edges the robot took more often: the transitive reduction leaves the edge out.
TEST(GraphCleanup, DropsARedundantEdge) {
  // A loop of 12 places three times; the third time place 6 is skipped (5 -> 7).
  std::vector<PlaceLabel> labels;
  for (int pass = 0; pass < 3; ++pass) {
    for (PlaceLabel p = 0; p < 12; ++p) {
      if (pass < 2 || p != 6) labels.push_back(p);
    }
  }
  const Case c = make_case(labels, {});
  TopologyConfig topology;
  EXPECT_EQ(build_topology(labels, {}, {}, topology).edges.size(), 13U);
  topology.reduce_transitive = true;
  const TopologicalMap map = build_topology(labels, {}, {}, topology);
  EXPECT_EQ(map.edges, cycle(12));
  EXPECT_TRUE(map.junctions.empty());
}

TEST(GraphCleanup, IsIdempotentAndChecksItsInput) {
  const Case c = corridor_case();
  const GraphCleanup once = clean_graph(c.labels, c.alignments, c.pruning, config_of(c));
  const GraphCleanup twice = clean_graph(once.labels, c.alignments, c.pruning, config_of(c));
  EXPECT_EQ(twice.labels, once.labels);
  PruningResult wrong = c.pruning;
  wrong.kept.push_back(true);
  EXPECT_THROW(clean_graph(c.labels, c.alignments, wrong, {}), std::invalid_argument);
  std::vector<PlaceLabel> short_labels(c.labels.begin(), c.labels.begin() + 5);
  EXPECT_THROW(clean_graph(short_labels, c.alignments, c.pruning, {}), std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::mapping
