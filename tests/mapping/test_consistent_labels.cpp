// Consistent labelling on hand-built alignment sets, with their exact place graphs: the mapping paper's three
// inconsistent alignments, several traversals, reverse, slower and zig-zagging passes, crossing alignments,
// shadows, refused chains, order independence, and the invariant (no place holds a long stretch of one pass) on
// random alignment sets.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>

#include "seqtopo/mapping/consistent_labels.hpp"
#include "seqtopo/mapping/place_labels.hpp"
#include "seqtopo/mapping/topological_map.hpp"

namespace seqtopo::mapping {
namespace {

using align::Direction;
using align::LocalAlignment;

// Later images i0.. paired with earlier images j0.. one to one (forward), or j0 + length - 1 down (reverse).
LocalAlignment run(std::size_t i0, std::size_t j0, std::size_t length, float score,
                   Direction direction = Direction::forward) {
  LocalAlignment a;
  a.score = score;
  a.direction = direction;
  for (std::size_t k = 0; k < length; ++k) {
    a.pairs.emplace_back(i0 + k, direction == Direction::forward ? j0 + k : j0 + length - 1 - k);
  }
  a.a_begin = i0;
  a.a_end = i0 + length;
  a.b_begin = j0;
  a.b_end = j0 + length;
  return a;
}

std::vector<double> scores_of(const std::vector<LocalAlignment>& alignments) {
  std::vector<double> p;
  for (const auto& a : alignments) p.push_back(a.score);
  return p;
}

ConsistentLabelling label(std::size_t n, const std::vector<LocalAlignment>& alignments, std::size_t min_separation = 5,
                          std::size_t span = 2) {
  return label_consistently(
      n, alignments, scores_of(alignments),
      {.min_separation = min_separation, .max_visit_span = span, .fill_gaps = true, .left_out = {}});
}

std::size_t count_places(const std::vector<PlaceLabel>& labels) {
  return std::set<PlaceLabel>(labels.begin(), labels.end()).size();
}

// The topological map of a labelling, as map_builder makes it (graph edges and junctions).
TopologicalMap graph_of(const ConsistentLabelling& r, const std::vector<LocalAlignment>& alignments) {
  return build_topology(r.labels, alignments, r.accepted);
}

// Edges (p, q), p < q, of a path through `places` in order.
std::vector<std::pair<PlaceLabel, PlaceLabel>> path_edges(std::vector<PlaceLabel> places) {
  std::vector<std::pair<PlaceLabel, PlaceLabel>> edges;
  for (std::size_t k = 1; k < places.size(); ++k) {
    edges.emplace_back(std::min(places[k - 1], places[k]), std::max(places[k - 1], places[k]));
  }
  return edges;
}

std::vector<std::pair<PlaceLabel, PlaceLabel>> sorted_unique(std::vector<std::pair<PlaceLabel, PlaceLabel>> edges) {
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

// The place graph of `r` is the walk `walk` (places in the order the robot met them, written from the labels of
// the frames that define them) and nothing else, and its junctions are `junctions`.
void expect_graph(const ConsistentLabelling& r, const std::vector<LocalAlignment>& alignments,
                  const std::vector<PlaceLabel>& walk, std::vector<PlaceLabel> junctions) {
  const auto map = graph_of(r, alignments);
  EXPECT_EQ(map.edges, sorted_unique(path_edges(walk)));
  std::sort(junctions.begin(), junctions.end());
  EXPECT_EQ(map.junctions, junctions);
}

// The labels of frames first..last (inclusive), backwards when first > last.
std::vector<PlaceLabel> labels_of(const ConsistentLabelling& r, std::size_t first, std::size_t last) {
  std::vector<PlaceLabel> out;
  for (std::size_t k = first;; k = first <= last ? k + 1 : k - 1) {
    out.push_back(r.labels[k]);
    if (k == last) break;
  }
  return out;
}

std::vector<PlaceLabel> operator+(std::vector<PlaceLabel> a, const std::vector<PlaceLabel>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

TEST(ConsistentLabels, ThePapersThreeInconsistentAlignmentsDoNotCollapse) {
  // Section IV-C: 1..5 = 11..15, 11..15 = 21..25 and 1..5 = 22..26 (one image off).
  const std::vector<LocalAlignment> alignments = {run(11, 1, 5, 10), run(21, 11, 5, 9), run(22, 1, 5, 8)};
  const auto r = label(30, alignments);
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(r.labels[1 + k], r.labels[11 + k]) << k;
    EXPECT_EQ(r.labels[11 + k], r.labels[21 + k]) << k;
    if (k > 0) {
      EXPECT_NE(r.labels[1 + k], r.labels[k]) << k;
    }
  }
  EXPECT_TRUE(r.accepted.kept[0] && r.accepted.kept[1]);
  EXPECT_FALSE(r.accepted.kept[2]) << "the third alignment restates the first two one image off";
  EXPECT_EQ(r.redundant, 5U);
  // Transitive closure of every pair chains 1 = 11 = 21 = ... = 26 into far fewer places.
  std::vector<std::pair<std::size_t, std::size_t>> all;
  for (const auto& a : alignments) all.insert(all.end(), a.pairs.begin(), a.pairs.end());
  EXPECT_LT(count_places(label_places(30, all)), count_places(r.labels));
  const auto transitive = label_places(30, all);
  EXPECT_EQ(transitive[1], transitive[5]) << "the closure puts a whole pass in one place";
  EXPECT_NE(r.labels[1], r.labels[5]);
  // The graph: the stretch 1..5 walked three times, with the loops 6..10, 16..20 and the tail 26..29 between;
  // its ends (the places of 1 and 5) are the junctions.
  EXPECT_EQ(count_places(r.labels), 30U - 10U);
  expect_graph(
      r, alignments,
      labels_of(r, 0, 10) + labels_of(r, 1, 5) + labels_of(r, 16, 20) + labels_of(r, 1, 5) + labels_of(r, 26, 29),
      {r.labels[1], r.labels[5]});
}

TEST(ConsistentLabels, ThreeTraversalsOfOnePathShareTheirPlaces) {
  const std::vector<LocalAlignment> alignments = {run(40, 0, 20, 10), run(80, 40, 20, 9), run(80, 0, 20, 8)};
  const auto r = label(100, alignments, 10);
  for (std::size_t k = 0; k < 20; ++k) {
    EXPECT_EQ(r.labels[k], r.labels[40 + k]) << k;
    EXPECT_EQ(r.labels[k], r.labels[80 + k]) << k;
  }
  EXPECT_EQ(count_places(r.labels), 100U - 40U);
  EXPECT_EQ(r.refused, 0U);
  EXPECT_EQ(r.redundant, 0U) << "the third alignment agrees with the first two: its pairs are already merged";
  EXPECT_EQ(r.accepted.pairs.size(), 60U);
  // The graph: the loop 0..39, the stretch 0..19 again, the loop 60..79 back to 0, the stretch once more.
  expect_graph(r, alignments, labels_of(r, 0, 39) + labels_of(r, 0, 19) + labels_of(r, 60, 79) + labels_of(r, 0, 19),
               {r.labels[0], r.labels[19]});
}

TEST(ConsistentLabels, AReverseTraversalPairsEachImageWithItsMirror) {
  const std::vector<LocalAlignment> alignments = {run(40, 0, 20, 10, Direction::reverse)};
  const auto r = label(60, alignments, 10);
  for (std::size_t k = 0; k < 20; ++k) EXPECT_EQ(r.labels[40 + k], r.labels[19 - k]) << k;
  EXPECT_NE(r.labels[0], r.labels[1]);
  // The graph: out along 0..39, then from 39 back onto the path at 19 and down it to 0: a junction at 19.
  EXPECT_EQ(count_places(r.labels), 40U);
  expect_graph(r, alignments, labels_of(r, 0, 39) + labels_of(r, 19, 0), {r.labels[19]});
}

// A revisit whose later pass has a stretch left out of the alignment (masked: 30 dark frames, 60-89, the alignment
// stepping from 59 to 90 over them): those frames are no slower pass holding a place, so they join no place and are
// no loop closure; without the flags the gap would fill them into the place before it.
TEST(ConsistentLabels, FramesLeftOutOfTheAlignmentAreNotFilledIntoItsGap) {
  LocalAlignment a;
  a.score = 10;
  for (std::size_t k = 0; k < 20; ++k) a.pairs.emplace_back(40 + k, k);   // 40-59 with 0-19
  for (std::size_t k = 20; k < 35; ++k) a.pairs.emplace_back(70 + k, k);  // 90-104 with 20-34
  a.a_begin = 40;
  a.a_end = 105;
  a.b_begin = 0;
  a.b_end = 35;
  std::vector<bool> left_out(110, false);
  for (std::size_t f = 60; f < 90; ++f) left_out[f] = true;
  const auto r = label_consistently(
      110, {a}, {10.0}, {.min_separation = 10, .max_visit_span = 2, .fill_gaps = true, .left_out = left_out});
  for (const auto& p : r.accepted.pairs) EXPECT_FALSE(left_out[p.i] || left_out[p.j]) << p.i << " " << p.j;
  EXPECT_EQ(r.accepted.pairs.size(), 35U);
  for (std::size_t f = 60; f < 90; ++f) EXPECT_NE(r.labels[f], r.labels[19]) << f;
  const auto filled = label(110, {a}, 10);  // no flags: the gap's first frames join 19's place
  EXPECT_GT(filled.accepted.pairs.size(), 35U);
  EXPECT_EQ(filled.labels[60], filled.labels[19]);
}

TEST(ConsistentLabels, AHalfSpeedPassFillsItsGapsWithoutBubbles) {
  // The second pass sees every image of the first twice: the alignment pairs every other frame.
  LocalAlignment a;
  a.score = 10;
  for (std::size_t k = 0; k < 20; ++k) a.pairs.emplace_back(40 + 2 * k, k);
  a.a_begin = 40;
  a.a_end = 79;
  a.b_begin = 0;
  a.b_end = 20;
  const auto r = label(80, {a}, 10);
  for (std::size_t k = 0; k < 19; ++k) {
    EXPECT_EQ(r.labels[40 + 2 * k], r.labels[k]) << k;
    EXPECT_EQ(r.labels[41 + 2 * k], r.labels[k]) << "the frame skipped by the gap joins the place before it";
  }
  // Each skipped frame is also a loop closure with the partner of the pair before it, in order of i.
  ASSERT_EQ(r.accepted.pairs.size(), 39U);
  for (std::size_t k = 0; k < 39; ++k) {
    EXPECT_EQ(r.accepted.pairs[k].i, 40 + k);
    EXPECT_EQ(r.accepted.pairs[k].j, k / 2);
    EXPECT_EQ(r.accepted.pairs[k].alignment, 0U);
  }
  EXPECT_EQ(r.accepted.retained_count[0], 20U);  // the alignment's own pairs
  // The graph: the loop 0..39, then 0..19 again at half speed, and the last frame (79, after the last pair)
  // somewhere new: the path leaves at 19.
  EXPECT_EQ(count_places(r.labels), 41U);
  expect_graph(r, {a}, labels_of(r, 0, 39) + labels_of(r, 0, 19) + labels_of(r, 79, 79), {r.labels[19]});
  const auto no_fill = label_consistently(
      80, {a}, {10.0}, {.min_separation = 10, .max_visit_span = 2, .fill_gaps = false, .left_out = {}});
  EXPECT_NE(no_fill.labels[41], no_fill.labels[0]);
  EXPECT_EQ(no_fill.accepted.pairs.size(), 20U);
  // With a span of one frame the slower pass may not hold a place for two frames.
  const auto strict = label(80, {a}, 10, 0);
  EXPECT_NE(strict.labels[41], strict.labels[0]);
  EXPECT_EQ(strict.accepted.pairs.size(), 20U);  // a frame refused by its place is no loop closure
}

TEST(ConsistentLabels, AZigZagPassHoldsEachPlaceForAFewFramesAndClosesOneCycle) {
  // A loop of 40 images (places 0..39), then a second pass over places 0..19 that zig-zags: it holds each place
  // for one to three frames, so its alignment pairs a frame here and there and skips the rest by gaps.
  const std::vector<std::size_t> frames_per_place = {1, 2, 3, 1, 2, 2, 3, 1, 1, 2, 3, 2, 1, 2, 2, 3, 1, 2, 2, 1};
  LocalAlignment a;
  a.score = 10;
  std::vector<std::size_t> place_of_frame;  // the true place of each frame of the second pass
  for (std::size_t p = 0; p < frames_per_place.size(); ++p) {
    a.pairs.emplace_back(40 + place_of_frame.size(), p);  // the first frame at each place is aligned
    for (std::size_t f = 0; f < frames_per_place[p]; ++f) place_of_frame.push_back(p);
  }
  const std::size_t n = 40 + place_of_frame.size();
  a.a_begin = 40;
  a.a_end = n;  // the last frame is the last pair
  a.b_begin = 0;
  a.b_end = 20;
  const std::vector<LocalAlignment> alignments = {a};
  const auto r = label(n, alignments, 10, 3);
  for (std::size_t f = 0; f < place_of_frame.size(); ++f) {
    EXPECT_EQ(r.labels[40 + f], r.labels[place_of_frame[f]]) << "frame " << 40 + f;
  }
  EXPECT_EQ(count_places(r.labels), 40U);
  // The graph: one cycle, the loop 0..39 closed by the second pass's return to place 0; the pass ends at place
  // 19, where the sequence stops (no junction: the path does not leave the old one, it ends).
  expect_graph(r, alignments, labels_of(r, 0, 39) + labels_of(r, 0, 19), {});
  EXPECT_EQ(graph_of(r, alignments).edges.size(), 40U);
}

TEST(ConsistentLabels, TwoCrossingAlignmentsKeepTheStrongerOnesPlaces) {
  // Images 40..59 revisit 0..19 forward (the true revisit, stronger); a weaker reverse alignment of the same
  // images crosses it in the middle of the matrix (49/50 against 10/9), as a corridor that looks alike both
  // ways gives. Then 60..69 go somewhere new.
  const std::vector<LocalAlignment> alignments = {run(40, 0, 20, 10), run(40, 0, 20, 6, Direction::reverse)};
  const auto r = label(70, alignments, 10);
  for (std::size_t k = 0; k < 20; ++k) EXPECT_EQ(r.labels[40 + k], r.labels[k]) << k;
  EXPECT_TRUE(r.accepted.kept[0]);
  EXPECT_FALSE(r.accepted.kept[1]) << "the crossing alignment would fold the first pass onto itself";
  EXPECT_EQ(r.redundant, 20U) << "every pair of the crossing alignment: the forward one placed its images";
  EXPECT_EQ(r.refused, 0U);
  EXPECT_EQ(count_places(r.labels), 50U);
  // The graph: the loop 0..39, along 0..19 again, then off to 60..69 from place 19, its one junction.
  expect_graph(r, alignments, labels_of(r, 0, 39) + labels_of(r, 0, 19) + labels_of(r, 60, 69), {r.labels[19]});
}

TEST(ConsistentLabels, AShadowBesideARevisitAddsNothing) {
  // The local aligner also reports the diagonal one image beside the revisit, a little weaker.
  const std::vector<LocalAlignment> alignments = {run(40, 1, 20, 9), run(40, 0, 20, 10)};
  const auto r = label(60, alignments, 10);
  for (std::size_t k = 0; k < 20; ++k) EXPECT_EQ(r.labels[40 + k], r.labels[k]) << k;
  for (std::size_t k = 1; k < 20; ++k) EXPECT_NE(r.labels[k], r.labels[k - 1]) << k;
  EXPECT_TRUE(r.accepted.kept[1]);
  EXPECT_FALSE(r.accepted.kept[0]) << "the shadow (listed first, weaker) is not a revisit of its own";
  EXPECT_EQ(r.redundant, 20U);
}

TEST(ConsistentLabels, AMergeThatPutsAStretchOfOnePassInOnePlaceIsRefused) {
  // 40..44 = 0..4 and 80..84 = 5..9; then 80..84 = 40..44 would join images k and k + 5 of the first pass.
  const std::vector<LocalAlignment> alignments = {run(40, 0, 5, 10), run(80, 5, 5, 9), run(80, 40, 5, 8)};
  const auto r = label(100, alignments, 10);
  EXPECT_EQ(r.refused, 5U);
  EXPECT_FALSE(r.accepted.kept[2]);
  // Transitive closure would have made them one place.
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(r.labels[40 + k], r.labels[k]);
    EXPECT_EQ(r.labels[80 + k], r.labels[5 + k]);
    EXPECT_NE(r.labels[80 + k], r.labels[40 + k]);
  }
  // A wider span allows it (5 frames of one pass in one place).
  EXPECT_EQ(label(100, alignments, 10, 5).refused, 0U);
}

TEST(ConsistentLabels, TheResultDoesNotDependOnTheOrderOfTheAlignments) {
  std::vector<LocalAlignment> alignments = {run(40, 0, 10, 10), run(80, 5, 10, 9), run(80, 40, 10, 9),
                                            run(60, 20, 8, 9, Direction::reverse), run(41, 0, 10, 7)};
  const auto reference = label(100, alignments, 10);
  std::mt19937 rng(3);
  for (int trial = 0; trial < 10; ++trial) {
    std::vector<std::size_t> order(alignments.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<LocalAlignment> shuffled;
    for (auto k : order) shuffled.push_back(alignments[k]);
    const auto r = label(100, shuffled, 10);
    EXPECT_EQ(r.labels, reference.labels) << trial;
    EXPECT_EQ(r.refused, reference.refused);
    EXPECT_EQ(r.redundant, reference.redundant);
    for (std::size_t k = 0; k < order.size(); ++k) {
      EXPECT_EQ(r.accepted.kept[k], reference.accepted.kept[order[k]]) << trial << " " << k;
    }
  }
}

// The span of the longest stretch of one pass within one place, by brute force over the labels.
std::size_t longest_stretch(const std::vector<PlaceLabel>& labels, std::size_t min_separation) {
  std::map<PlaceLabel, std::vector<std::size_t>> members;
  for (std::size_t k = 0; k < labels.size(); ++k) members[labels[k]].push_back(k);
  std::size_t longest = 0;
  for (const auto& [place, m] : members) {
    std::size_t start = m.front();
    for (std::size_t k = 1; k < m.size(); ++k) {
      if (m[k] - m[k - 1] >= min_separation) start = m[k];
      longest = std::max(longest, m[k] - start);
    }
  }
  return longest;
}

TEST(ConsistentLabels, RandomAlignmentSetsKeepEveryPassShortInAPlaceAndTheirPairsTogether) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t n = 200;
    std::vector<LocalAlignment> alignments;
    const int count = 1 + static_cast<int>(rng() % 8);
    for (int k = 0; k < count; ++k) {
      const std::size_t length = 3 + rng() % 15;
      const std::size_t j0 = rng() % (n - length - 30);
      const std::size_t i0 = j0 + length + 10 + rng() % (n - j0 - 2 * length - 10);
      alignments.push_back(
          run(i0, j0, length, static_cast<float>(rng() % 5), rng() % 2 == 0 ? Direction::forward : Direction::reverse));
    }
    const std::size_t span = rng() % 4;
    const auto r = label(n, alignments, 10, span);
    EXPECT_LE(longest_stretch(r.labels, 10), span) << trial;
    for (const auto& p : r.accepted.pairs) EXPECT_EQ(r.labels[p.i], r.labels[p.j]) << trial;
    std::size_t proposals = 0;
    for (const auto& a : alignments) proposals += a.pairs.size();
    EXPECT_EQ(r.accepted.pairs.size() + r.refused + r.redundant, proposals) << trial;
  }
}

TEST(ConsistentLabels, BadInputIsAnError) {
  EXPECT_THROW(label_consistently(10, {run(5, 0, 2, 1)}, {}, {}), std::invalid_argument);
  EXPECT_THROW(label(10, {run(9, 0, 3, 1)}), std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::mapping
