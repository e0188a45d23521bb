#pragma once
// Transitive labeling (mapping paper, IV-C): images joined by a retained pair, directly or through
// other images, share a place label. Labels are numbered in order of first appearance in the
// sequence (image 0 has label 0), so the result does not depend on the order of the pairs.
#include <cstddef>
#include <utility>
#include <vector>

namespace seqtopo::mapping {

using PlaceLabel = int;

std::vector<PlaceLabel> label_places(std::size_t images,
                                     const std::vector<std::pair<std::size_t, std::size_t>>& same_place);

}  // namespace seqtopo::mapping
