#pragma once
// Clean-up of the place graph the way genome assemblers clean their assembly graphs, before the topology is
// read from it. A map labels every image; the places are nodes, and consecutive images of one session join
// their places. Noise in the labelling leaves the same small structures an assembly graph gets from
// sequencing errors, and they are removed with the same kind of rules, each with a threshold that follows
// from the sequence's own alignments and place scale (never from ground truth):
//
//  1. Overhangs (Li 2016, miniasm: an overlap whose unaligned ends are short, at most (1 - int_frac) of the
//     mapping, is extended to the reads' ends). A local alignment's score builds up only once it has started,
//     so a revisit that runs to the start or end of a session stops a few images short of it, and the
//     unaligned images become a dead end beside the revisited path. When one traversal of a kept alignment
//     reaches its session's end within `hang_fraction` of the alignment's length (in pairs), the alignment is
//     extended pair by pair (one image each, in its direction) to that end: each image of the short side
//     joins the place of its counterpart.
//  2. Tips (Zerbino & Birney 2008, Velvet's tip clipping: dead ends shorter than 2k are removed). A dead-end
//     chain of places seen by one pass, with at most `max_tip_frames` images (the shortest revisit an
//     alignment may report: nothing shorter can be told apart from the place it hangs from), joins the place
//     where it meets the rest of the graph.
//  3. Bubbles (Velvet's Tour Bus bubble popping: two short paths between the same nodes, the one with less
//     coverage merged into the other). A chain of places whose inner places each have two neighbours, from a
//     place p to a place q, with at most `max_bubble_frames` images, and another route from p to q of at most
//     as many places: the route seen by fewer passes is merged into the other. The chain's images are spread
//     over the other route in their order (halves to p and q when the other route is the edge p - q). When
//     both are seen equally often, the route first driven later is merged (pop_ties_by_time: the first visit
//     defines the places, and a detour shorter than any revisit is no route of its own; Velvet likewise pops
//     a bubble of alike paths whatever its coverage), or, with pop_ties_by_time off, only a chain an accepted
//     alignment spans, pairing the images just before and just after it (skipped by a gap). A chain that comes back to
//     the place it left (a hairpin: a U-turn whose two legs were not merged), of single-pass places and at most
//     `max_bubble_frames` images, becomes one place.
//  4. Redundant edges (miniasm's transitive reduction): an edge p - q, traversed less often than both edges
//     of a route p - x - q, is a pass that went past x between two images (a faster pass); topological_map
//     drops it (TopologyConfig::reduce_transitive).
//
// Pure function: labels in, labels out.
#include <cstddef>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/mapping/place_labels.hpp"
#include "seqtopo/mapping/pruning.hpp"

namespace seqtopo::mapping {

struct GraphCleanupConfig {
  double hang_fraction = 0.2;         // longest overhang extended, as a fraction of the alignment's pairs
  std::size_t max_tip_frames = 3;     // [frames] longest tip clipped
  std::size_t max_bubble_frames = 3;  // [frames] longest chain of a bubble that is popped
  std::size_t min_separation = 10;    // [frames] images closer in time are one pass
  // Rule 3 when both routes are seen by as many passes: true merges the route first driven later (the first
  // visit defines the places; a detour shorter than any revisit is no route of its own, as Velvet pops a bubble
  // whatever its coverage when its paths are alike), false only a chain an accepted alignment spans.
  bool pop_ties_by_time = true;
  std::vector<std::size_t> session_starts;  // the first image of each session after the first
};

struct GraphCleanup {
  std::vector<PlaceLabel> labels;  // per image, renumbered in order of first appearance
  std::size_t extended_images = 0, clipped_images = 0, popped_images = 0;  // images moved by each rule
};

// `pruning` gives the accepted pairs of `alignments` (its `kept` flags and `pairs`). Throws
// std::invalid_argument when the sizes disagree.
GraphCleanup clean_graph(const std::vector<PlaceLabel>& labels, const std::vector<align::LocalAlignment>& alignments,
                         const PruningResult& pruning, const GraphCleanupConfig& config = {});

}  // namespace seqtopo::mapping
