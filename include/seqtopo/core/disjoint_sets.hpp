#pragma once
// Disjoint sets (union-find) whose root is the smallest element of its set, so that a set is named by its first
// member whatever order the joins come in (a place by its first frame, a component by its first cell). Finding
// halves the path; joining puts the larger root under the smaller (Tarjan & van Leeuwen 1984: halving alone
// keeps the amortized cost logarithmic, ample for the sequences here).
#include <cstddef>
#include <utility>
#include <vector>

namespace seqtopo {

template <typename Index = std::size_t>
class DisjointSets {
 public:
  DisjointSets() = default;
  explicit DisjointSets(std::size_t n) {
    parent_.reserve(n);
    size_.reserve(n);
    for (std::size_t k = 0; k < n; ++k) add();
  }

  // A new set of one element; returns it (the number of elements before).
  Index add() {
    parent_.push_back(static_cast<Index>(parent_.size()));
    size_.push_back(1);
    return parent_.back();
  }
  // The root of x's set: its smallest element.
  Index find(Index x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  // Joins the sets of a and b; returns (the joined set's root, the root it absorbed), equal when a and b were in
  // one set already.
  std::pair<Index, Index> unite(Index a, Index b) {
    a = find(a);
    b = find(b);
    if (b < a) std::swap(a, b);
    if (a != b) {
      parent_[b] = a;
      size_[a] += size_[b];
    }
    return {a, b};
  }
  // Elements in the set of the root `root`.
  std::size_t set_size(Index root) const { return size_[root]; }
  std::size_t size() const { return parent_.size(); }

 private:
  std::vector<Index> parent_;
  std::vector<std::size_t> size_;
};

}  // namespace seqtopo
