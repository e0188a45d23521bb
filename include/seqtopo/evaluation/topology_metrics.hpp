#pragma once
// How well the map's places match the true places (INTERFACE.md, "topology" in metrics.json).
//
// Granularity: the map gives every image its own place unless an alignment merges it with an image of
// another traversal, while a true place is a stretch of path (several consecutive images). Compared as
// they are, a perfect map would score near 0. So the map's partition is first coarsened along time only:
// consecutive images i, i+1 of the same true place are joined (what one traversal sees of one place),
// and the map's merges across traversals are kept. A map that merges every revisit with the right place
// and nothing else then equals the truth; a wrong merge joins two true places; a missed one leaves a
// place split by traversal. A merge of two images of neighbouring true places that are still the same
// place by the loop-closure ground truth (`tolerated`, e.g. within its radius) is neither: an alignment
// off by one image at a place boundary must not chain the places of a whole corridor together. Nor is a
// map place that holds two images of one pass on either side of one true-place boundary (fewer than
// pass_frames apart, min_separation in evaluate_topology): a slow or zig-zagging pass holds a place for a
// few frames, and where a true place ends inside that visit is the truth's granularity, not a wrong merge.
//  * adjusted_rand_index: agreement of the coarsened map partition with the true places (1 = identical,
//    ~0 = chance); adjusted_rand_index_frames: the same without coarsening (the raw per-image labels);
//  * false_merges: image pairs (i, j), i - j >= min_separation, that the coarsened map puts in one place
//    but that are different true places; missed_merges: the same true place, different coarsened map
//    places (pairs closer in time than min_separation are not revisits and are not counted);
//  * junctions: a true junction (a true place id) is matched when some image of a junction place of
//    the map lies in that true place, or within junction_tolerance frames of an image that does.
#include <cstddef>
#include <functional>
#include <vector>

namespace seqtopo::evaluation {

struct TopologyMetrics {
  double adjusted_rand_index = 0;
  double adjusted_rand_index_frames = 0;
  std::size_t false_merges = 0, missed_merges = 0;
  std::size_t junctions_true = 0, junctions_found = 0, junctions_matched = 0;
};

double adjusted_rand_index(const std::vector<int>& a, const std::vector<int>& b);

// The map's labels joined along runs of consecutive images in the same true place (see above); labels are
// renumbered 0, 1, ... in order of first image.
using Tolerated = std::function<bool(std::size_t, std::size_t)>;
std::vector<int> coarsen_along_true_places(const std::vector<int>& map_labels, const std::vector<int>& true_places,
                                           const Tolerated& tolerated = {}, std::size_t pass_frames = 0);

TopologyMetrics evaluate_topology(const std::vector<int>& map_labels, const std::vector<int>& map_junctions,
                                  const std::vector<int>& true_places, const std::vector<int>& true_junctions,
                                  std::size_t min_separation, std::size_t junction_tolerance = 2,
                                  const Tolerated& tolerated = {});

}  // namespace seqtopo::evaluation
