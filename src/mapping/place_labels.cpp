#include "seqtopo/mapping/place_labels.hpp"

#include <numeric>
#include <stdexcept>
#include <string>

namespace seqtopo::mapping {
namespace {

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n), rank_(n, 0) { std::iota(parent_.begin(), parent_.end(), 0); }
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];  // path halving
      x = parent_[x];
    }
    return x;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (rank_[a] < rank_[b]) std::swap(a, b);
    parent_[b] = a;
    if (rank_[a] == rank_[b]) ++rank_[a];
  }

 private:
  std::vector<std::size_t> parent_;
  std::vector<unsigned char> rank_;
};

}  // namespace

std::vector<PlaceLabel> label_places(std::size_t images,
                                     const std::vector<std::pair<std::size_t, std::size_t>>& same_place) {
  UnionFind sets(images);
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
