#pragma once
// One consistent labelling from all alignments: the mapping paper's own future work (section IV-C: "the
// ideal solution to this problem is to perform ... multiple string alignment"), in the consistency-based
// form of progressive multiple aligners: the traversals are merged place by place, the most significant
// evidence first, and a merge that the traversals' order forbids is refused instead of chained.
//
// Places are sets of images. Two images closer in time than min_separation belong to one pass of the
// robot; a place may hold several passes (each a revisit) but within one pass only a stretch of at most
// max_visit_span frames (a slow or zig-zagging pass holds a place for a few frames, never for the length of a
// corridor). Every aligned pair (i, j) proposes to merge the places of i and j. The proposals are taken by
// alignment, most significant first (ties: direction, then a_begin, then b_begin, so the result does not
// depend on the order the alignments are given in), each alignment's pairs in increasing i. A proposal (i, j)
// is redundant when i's place already holds another image of j's pass (or j's place one of i's pass): that
// pass has matched there already, and the proposal is a shadow of the match (the diagonal a few frames
// beside a revisit, which a local aligner also reports). It is redundant too when a stronger alignment already
// matched i into the stretch of images that j lies in (the first..last image of that alignment's accepted
// pairs on j's side), or j into i's: that alignment has said where in the stretch i lies, and a weaker one that
// crosses it (a reverse alignment of a forward revisit, say) would fold the stretch onto itself at places more
// than min_separation apart, which the pass rule cannot see. Otherwise it is accepted when the merged place
// still holds no pass longer than max_visit_span frames, else refused.
//
// The paper's three inconsistent alignments (1..5 = 11..15, 11..15 = 21..25, 1..5 = 22..26) thus give the
// places {1, 11, 21}, {2, 12, 22}, ...: the third alignment is redundant (1's place already holds 21 of the
// pass 21..26), instead of collapsing all sixteen images into one place as transitive closure does. Three
// traversals of one path and a reverse traversal merge into the same places; a shadow's pairs past the end
// of the stronger alignment extend the revisit.
//
// Gaps: an image inside an accepted alignment's range that got no pair of its own (skipped by a gap, a slow
// pass holding a place) joins the place of the image before it when that keeps the place consistent, so a
// revisit at another speed leaves no bubble of unmerged images. Such an image of the later pass is a loop
// closure with the partner of the pair before it, and is listed with the accepted pairs.
#include <cstddef>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/mapping/place_labels.hpp"
#include "seqtopo/mapping/pruning.hpp"

namespace seqtopo::mapping {

struct ConsistentLabellingConfig {
  std::size_t min_separation = 10;  // [frames] images closer in time are one pass
  std::size_t max_visit_span = 2;   // [frames] the longest stretch of one pass within one place
  bool fill_gaps = true;
  // Frames the alignments left out (masked: no evidence of where they are; empty: none): never filled into a
  // gap, as a stretch of them skipped by one pass is not a slower pass holding a place.
  std::vector<bool> left_out;
};

struct ConsistentLabelling {
  std::vector<PlaceLabel> labels;  // per image, numbered in order of first appearance
  // The accepted pairs as a pruning result: `kept` when at least min_kept_fraction of an alignment's pairs were
  // accepted, `retained_count` its accepted pairs, `pairs` every accepted pair (i > j), by alignment then i,
  // with the skipped images of the later pass that joined a place (see Gaps; not in retained_count).
  PruningResult accepted;
  std::size_t refused = 0;    // proposals refused as inconsistent
  std::size_t redundant = 0;  // proposals whose pass had already matched the other image's place (shadows)
};

// `priority[k]` ranks alignment k (higher first; e.g. its path score). Throws std::invalid_argument when the
// sizes disagree or a pair lies outside the images.
ConsistentLabelling label_consistently(std::size_t images, const std::vector<align::LocalAlignment>& alignments,
                                       const std::vector<double>& priority, const ConsistentLabellingConfig& config,
                                       double min_kept_fraction = 0.5);

}  // namespace seqtopo::mapping
