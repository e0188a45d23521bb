#include "seqtopo/evaluation/topology_metrics.hpp"

#include <iterator>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>
#include <utility>

#include "seqtopo/core/disjoint_sets.hpp"

namespace seqtopo::evaluation {
namespace {
double choose2(double n) { return n * (n - 1) / 2; }
}  // namespace

double adjusted_rand_index(const std::vector<int>& a, const std::vector<int>& b) {
  if (a.size() != b.size()) throw std::invalid_argument("partitions of different sizes");
  std::map<std::pair<int, int>, double> joint;
  std::map<int, double> ca, cb;
  for (std::size_t k = 0; k < a.size(); ++k) {
    joint[{a[k], b[k]}] += 1;
    ca[a[k]] += 1;
    cb[b[k]] += 1;
  }
  double index = 0, sum_a = 0, sum_b = 0;
  for (const auto& [key, n] : joint) index += choose2(n);
  for (const auto& [key, n] : ca) sum_a += choose2(n);
  for (const auto& [key, n] : cb) sum_b += choose2(n);
  const double total = choose2(static_cast<double>(a.size()));
  if (total == 0) return 1.0;
  const double expected = sum_a * sum_b / total;
  const double max_index = (sum_a + sum_b) / 2;
  if (max_index == expected) return 1.0;  // both partitions trivial (all singletons or one block)
  return (index - expected) / (max_index - expected);
}

std::vector<int> coarsen_along_true_places(const std::vector<int>& map_labels, const std::vector<int>& true_places,
                                           const Tolerated& tolerated, std::size_t pass_frames) {
  if (map_labels.size() != true_places.size()) throw std::invalid_argument("partitions of different sizes");
  const std::size_t n = map_labels.size();
  // boundaries[k]: changes of true place among images 0..k.
  std::vector<std::size_t> boundaries(n, 0);
  for (std::size_t k = 1; k < n; ++k) boundaries[k] = boundaries[k - 1] + (true_places[k] != true_places[k - 1]);
  const auto neighbours_in_one_pass = [&](std::size_t i, std::size_t j) {
    if (i > j) std::swap(i, j);
    return j - i < pass_frames && boundaries[j] - boundaries[i] == 1;
  };
  DisjointSets<std::size_t> sets(n);
  const auto find = [&](std::size_t x) { return sets.find(x); };
  const auto unite = [&](std::size_t a, std::size_t b) { sets.unite(a, b); };
  // Images of each map place, grouped by true place.
  std::map<int, std::map<int, std::vector<std::size_t>>> groups;
  for (std::size_t i = 0; i < n; ++i) {
    groups[map_labels[i]][true_places[i]].push_back(i);
    if (i + 1 < n && true_places[i] == true_places[i + 1]) unite(i, i + 1);
  }
  for (const auto& [label, by_place] : groups) {
    for (const auto& [place, images] : by_place) {
      for (std::size_t k = 1; k < images.size(); ++k) unite(images.front(), images[k]);
    }
    // Two true places in one map place: joined unless every pair of their images is tolerated.
    for (auto a = by_place.begin(); a != by_place.end(); ++a) {
      for (auto b = std::next(a); b != by_place.end(); ++b) {
        bool all_tolerated = true;
        for (std::size_t i : a->second) {
          for (std::size_t j : b->second) {
            all_tolerated = all_tolerated && (neighbours_in_one_pass(i, j) || (tolerated && tolerated(i, j)));
          }
        }
        if (!all_tolerated) unite(a->second.front(), b->second.front());
      }
    }
  }
  std::vector<int> out(n);
  std::map<std::size_t, int> renumber;
  for (std::size_t i = 0; i < n; ++i) {
    out[i] = renumber.emplace(find(i), static_cast<int>(renumber.size())).first->second;
  }
  return out;
}

TopologyMetrics evaluate_topology(const std::vector<int>& map_labels, const std::vector<int>& map_junctions,
                                  const std::vector<int>& true_places, const std::vector<int>& true_junctions,
                                  std::size_t min_separation, std::size_t junction_tolerance,
                                  const Tolerated& tolerated) {
  if (map_labels.size() != true_places.size()) {
    throw std::invalid_argument("the map has " + std::to_string(map_labels.size()) + " images, the ground truth " +
                                std::to_string(true_places.size()));
  }
  const std::size_t n = map_labels.size();
  TopologyMetrics m;
  const std::vector<int> coarse = coarsen_along_true_places(map_labels, true_places, tolerated, min_separation);
  m.adjusted_rand_index = adjusted_rand_index(coarse, true_places);
  m.adjusted_rand_index_frames = adjusted_rand_index(map_labels, true_places);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j + min_separation <= i; ++j) {
      const bool same_map = coarse[i] == coarse[j];
      const bool same_true = true_places[i] == true_places[j];
      m.false_merges += same_map && !same_true;
      m.missed_merges += !same_map && same_true;
    }
  }
  const std::set<int> truth(true_junctions.begin(), true_junctions.end());
  const std::set<int> found(map_junctions.begin(), map_junctions.end());
  m.junctions_true = truth.size();
  m.junctions_found = found.size();
  std::set<int> matched;
  for (std::size_t k = 0; k < n; ++k) {
    if (!found.count(map_labels[k])) continue;
    const std::size_t lo = k >= junction_tolerance ? k - junction_tolerance : 0;
    const std::size_t hi = std::min(n, k + junction_tolerance + 1);
    for (std::size_t q = lo; q < hi; ++q) {
      if (truth.count(true_places[q])) matched.insert(true_places[q]);
    }
  }
  m.junctions_matched = matched.size();
  return m;
}

}  // namespace seqtopo::evaluation
