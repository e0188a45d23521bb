#include "seqtopo/mapping/place_labels.hpp"

#include <numeric>
#include <stdexcept>
#include <string>

#include "seqtopo/core/disjoint_sets.hpp"

namespace seqtopo::mapping {

std::vector<PlaceLabel> label_places(std::size_t images,
                                     const std::vector<std::pair<std::size_t, std::size_t>>& same_place) {
  DisjointSets<std::size_t> sets(images);
  for (auto [i, j] : same_place) {
    if (i >= images || j >= images) {
      throw std::invalid_argument("pair (" + std::to_string(i) + ", " + std::to_string(j) + ") outside " +
                                  std::to_string(images) + " images");
    }
    sets.unite(i, j);
  }
  std::vector<PlaceLabel> root_label(images, -1);
  std::vector<PlaceLabel> labels(images);
  PlaceLabel next = 0;
  for (std::size_t k = 0; k < images; ++k) {
    const std::size_t root = sets.find(k);
    if (root_label[root] < 0) root_label[root] = next++;
    labels[k] = root_label[root];
  }
  return labels;
}

}  // namespace seqtopo::mapping
