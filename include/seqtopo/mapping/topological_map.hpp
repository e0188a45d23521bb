#pragma once
// The topological map (mapping paper, IV-C/D): places are the place labels, an edge joins the places
// of two consecutive images, junctions are where the robot's path branches or merges, and chains of
// places between junctions collapse into path segments.
//
// Junctions are the union of two tests:
//  * degree: a place with three or more neighbouring places;
//  * alignment boundary: at the first retained pair (i, j) of a kept alignment, the two traversals
//    arrived from different places (label[i-1] != label of j's predecessor along the alignment), or
//    at the last pair they leave to different places. Boundaries at the ends of the sequence
//    (no predecessor/successor) and U-turns (a reverse alignment meeting itself, |i - j| <=
//    u_turn_separation) are not junctions: the path starts, stops or turns back there.
//
// With reduce_transitive, the edges are those left by graph_cleanup.hpp's rule 4, and the degree test counts
// them.
//
// Junction regions: where three paths meet, the alignments that join and leave there end a place or two
// apart, so one junction on the ground shows as a knot of branching places (a tangle, in the language of
// assembly graphs). Places that pass either test and lie within junction_region edges of one another (single
// linkage) are one junction, reported at the knot's centre (the member with the smallest largest distance to
// the others; the smallest label of equals); `junction_regions` lists the places each junction stands for.
#include <cstddef>
#include <utility>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/mapping/place_labels.hpp"
#include "seqtopo/mapping/pruning.hpp"

namespace seqtopo::mapping {

struct Place {
  PlaceLabel id = 0;
  std::vector<std::size_t> images;  // in increasing order
};

struct PathSegment {
  std::vector<PlaceLabel> places;  // from one end (a junction or an end of the path) to the other
};

// What makes a place a junction, for a person to check: every pass of the robot through it (where it came from
// and went to), the alignments that begin or end there, the sessions involved, and a confidence.
struct JunctionPass {
  std::size_t first_image = 0, last_image = 0;  // the pass's images in the junction's places, [first, last]
  PlaceLabel from = -1, to = -1;                // the places before and after it; -1 at a session's start or end
  std::size_t session = 0;
};

struct JunctionEvidence {
  PlaceLabel place = 0;
  std::vector<PlaceLabel> branches;  // the neighbouring places (out of its region), sorted
  std::vector<JunctionPass> passes;  // in time order
  // Images where two traversals join or leave each other here: the first or last retained pair of an alignment
  // (both images), and the first image of a pass that arrives from, or the last of one that leaves to, a place no
  // other pass comes from or goes to.
  std::vector<std::size_t> images;      // sorted, unique
  std::vector<std::size_t> alignments;  // indices of kept alignments whose first or last retained pair is here
  std::vector<std::size_t> sessions;    // the sessions of the passes, sorted, unique
  bool by_degree = false;               // three or more neighbouring places
  bool by_alignment = false;            // an alignment's traversals arrive from or leave to different places here
  std::vector<PlaceLabel> region;       // the branching places this junction stands for (itself included), sorted
  // The largest confidence of the retained pairs that merged the place (the probability that the place is a
  // revisit at all, without which it would be no junction); 0 when no retained pair has an image here.
  double confidence = 0;
};

struct TopologicalMap {
  std::vector<PlaceLabel> labels;                         // one per image
  std::vector<Place> places;                              // indexed by label
  std::vector<std::pair<PlaceLabel, PlaceLabel>> edges;   // (p, q) with p < q, sorted, unique
  std::vector<PlaceLabel> junctions;                      // sorted
  std::vector<std::vector<PlaceLabel>> junction_regions;  // per junction: the places it stands for, sorted
  std::vector<PathSegment> segments;                      // sorted by first place
  std::vector<JunctionEvidence> junction_evidence;        // one per junction, in the order of `junctions`
};

struct TopologyConfig {
  std::size_t u_turn_separation = 10;  // [frames]
  // Several sessions mapped as one sequence: the first image of each session after the first. Image k - 1
  // and image k of such a k were not taken one after the other, so no edge joins their places, and neither is
  // the other's predecessor or successor for the junction test (as at the ends of a single sequence).
  std::vector<std::size_t> session_starts;
  // Transitive reduction (graph_cleanup.hpp, rule 4): an edge p - q traversed less often than both edges of a
  // route p - x - q is left out (a pass that went past x between two images).
  bool reduce_transitive = false;
  // [edges] branching places this close to one another are one junction (0: each is its own)
  std::size_t junction_region = 0;
};

TopologicalMap build_topology(const std::vector<PlaceLabel>& labels,
                              const std::vector<align::LocalAlignment>& alignments, const PruningResult& pruning,
                              const TopologyConfig& config = {});

// Fills map.junction_evidence from the map, its alignments and their retained pairs (with their confidences).
void describe_junctions(TopologicalMap& map, const std::vector<align::LocalAlignment>& alignments,
                        const PruningResult& pruning, const TopologyConfig& config = {});

}  // namespace seqtopo::mapping
