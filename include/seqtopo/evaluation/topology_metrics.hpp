#pragma once
// How well the map's places match the true places (INTERFACE.md, "topology" in metrics.json).
//  * adjusted_rand_index: agreement of the two partitions of the images (1 = identical, ~0 = chance);
//  * false_merges: image pairs (i, j), i - j >= min_separation, that the map puts in one place but
//    that are different true places; missed_merges: the same true place, different map places
//    (pairs closer in time than min_separation are not revisits and are not counted);
//  * junctions: a true junction (a true place id) is matched when some image of a junction place of
//    the map lies in that true place, or within junction_tolerance frames of an image that does.
#include <cstddef>
#include <vector>

namespace seqtopo::evaluation {

struct TopologyMetrics {
  double adjusted_rand_index = 0;
  std::size_t false_merges = 0, missed_merges = 0;
  std::size_t junctions_true = 0, junctions_found = 0, junctions_matched = 0;
};

double adjusted_rand_index(const std::vector<int>& a, const std::vector<int>& b);

TopologyMetrics evaluate_topology(const std::vector<int>& map_labels, const std::vector<int>& map_junctions,
                                  const std::vector<int>& true_places, const std::vector<int>& true_junctions,
                                  std::size_t min_separation, std::size_t junction_tolerance = 2);

}  // namespace seqtopo::evaluation
