#include "seqtopo/mapping/consistent_labels.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

#include "seqtopo/core/disjoint_sets.hpp"

namespace seqtopo::mapping {
namespace {

// The images first..last of one traversal (inclusive).
struct Stretch {
  std::size_t first = 0, last = 0;
};

// Places as disjoint sets (core/disjoint_sets.hpp) whose members are kept sorted, by root, so a merge can be
// checked against the passes.
class Places {
 public:
  explicit Places(std::size_t n) : sets_(n), members_(n) {
    for (std::size_t k = 0; k < n; ++k) members_[k] = {k};
  }
  std::size_t find(std::size_t x) { return sets_.find(x); }
  // Whether the place of `a` holds an image of the pass of `b` other than b itself: b's pass already
  // matched there, so pairing a with b again (a shadow of that match) would only widen the place.
  bool holds_pass_of(std::size_t a, std::size_t b, std::size_t min_separation) {
    const auto& m = members_[find(a)];
    const std::size_t low = b >= min_separation ? b - min_separation + 1 : 0;
    for (auto it = std::lower_bound(m.begin(), m.end(), low); it != m.end() && *it < b + min_separation; ++it) {
      if (*it != b) return true;
    }
    return false;
  }
  // Merges the places of a and b when no pass of the result spans more than max_span frames (a pass: members
  // closer than min_separation to the next). Returns whether they are now one place.
  bool merge(std::size_t a, std::size_t b, std::size_t min_separation, std::size_t max_span) {
    a = find(a);
    b = find(b);
    if (a == b) return true;
    std::vector<std::size_t> merged;
    merged.reserve(members_[a].size() + members_[b].size());
    std::merge(members_[a].begin(), members_[a].end(), members_[b].begin(), members_[b].end(),
               std::back_inserter(merged));
    std::size_t pass_start = merged.front();
    for (std::size_t k = 1; k < merged.size(); ++k) {
      if (merged[k] - merged[k - 1] >= min_separation) {
        pass_start = merged[k];
      } else if (merged[k] - pass_start > max_span) {
        return false;
      }
    }
    const auto [root, absorbed] = sets_.unite(a, b);
    members_[root] = std::move(merged);
    members_[absorbed].clear();
    members_[absorbed].shrink_to_fit();
    return true;
  }

 private:
  DisjointSets<std::size_t> sets_;
  std::vector<std::vector<std::size_t>> members_;
};

}  // namespace

ConsistentLabelling label_consistently(std::size_t images, const std::vector<align::LocalAlignment>& alignments,
                                       const std::vector<double>& priority, const ConsistentLabellingConfig& config,
                                       double min_kept_fraction) {
  if (priority.size() != alignments.size()) throw std::invalid_argument("one priority per alignment needed");
  if (!config.left_out.empty() && config.left_out.size() != images) {
    throw std::invalid_argument("left_out needs one flag per image");
  }
  for (const auto& a : alignments) {
    for (auto [i, j] : a.pairs) {
      if (i >= images || j >= images) {
        throw std::invalid_argument("pair (" + std::to_string(i) + ", " + std::to_string(j) + ") outside " +
                                    std::to_string(images) + " images");
      }
    }
  }
  // The canonical order: most significant first, then a fixed order of the alignments themselves.
  std::vector<std::size_t> order(alignments.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    if (priority[x] != priority[y]) return priority[x] > priority[y];
    const auto& ax = alignments[x];
    const auto& ay = alignments[y];
    if (ax.direction != ay.direction) return ax.direction == align::Direction::forward;
    if (ax.a_begin != ay.a_begin) return ax.a_begin < ay.a_begin;
    if (ax.b_begin != ay.b_begin) return ax.b_begin < ay.b_begin;
    return ax.pairs < ay.pairs;
  });

  Places places(images);
  ConsistentLabelling out;
  std::vector<std::vector<bool>> accepted(alignments.size());
  // Per image, the stretches of the other traversal that stronger alignments already matched it into.
  std::vector<std::vector<Stretch>> matched_into(images);
  const auto already_placed = [&](std::size_t x, std::size_t y) {
    return std::any_of(matched_into[x].begin(), matched_into[x].end(),
                       [y](const Stretch& s) { return s.first <= y && y <= s.last; });
  };
  for (std::size_t k : order) {
    const auto& a = alignments[k];
    accepted[k].assign(a.pairs.size(), false);
    for (std::size_t p = 0; p < a.pairs.size(); ++p) {
      const auto [i, j] = a.pairs[p];
      if (places.find(i) != places.find(j) &&
          (already_placed(i, j) || already_placed(j, i) || places.holds_pass_of(i, j, config.min_separation) ||
           places.holds_pass_of(j, i, config.min_separation))) {
        ++out.redundant;
      } else if (places.merge(i, j, config.min_separation, config.max_visit_span)) {
        accepted[k][p] = true;
      } else {
        ++out.refused;
      }
    }
    Stretch is{images, 0}, js{images, 0};
    for (std::size_t p = 0; p < a.pairs.size(); ++p) {
      if (!accepted[k][p]) continue;
      is = {std::min(is.first, a.pairs[p].first), std::max(is.last, a.pairs[p].first)};
      js = {std::min(js.first, a.pairs[p].second), std::max(js.last, a.pairs[p].second)};
    }
    for (std::size_t p = 0; p < a.pairs.size(); ++p) {
      if (!accepted[k][p]) continue;
      matched_into[a.pairs[p].first].push_back(js);
      matched_into[a.pairs[p].second].push_back(is);
    }
  }
  // Images skipped inside an accepted stretch of an alignment join the place of the image before them. An image
  // of the later pass (i) that does is a loop closure with the partner of the pair before it: a slower pass
  // holds that place for a few frames (align/pair_posterior.hpp, row_posteriors, puts it there too).
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> skipped(alignments.size());
  if (config.fill_gaps) {
    for (std::size_t k : order) {
      const auto& a = alignments[k];
      for (std::size_t p = 1; p < a.pairs.size(); ++p) {
        if (!accepted[k][p] || !accepted[k][p - 1]) continue;
        const auto fills = [&](std::size_t f) { return config.left_out.empty() || !config.left_out[f]; };
        for (std::size_t i = a.pairs[p - 1].first + 1; i < a.pairs[p].first && fills(i); ++i) {
          if (places.merge(i, i - 1, config.min_separation, config.max_visit_span)) {
            skipped[k].emplace_back(i, a.pairs[p - 1].second);
          }
        }
        const std::size_t j0 = std::min(a.pairs[p - 1].second, a.pairs[p].second);
        const std::size_t j1 = std::max(a.pairs[p - 1].second, a.pairs[p].second);
        for (std::size_t j = j0 + 1; j < j1 && fills(j); ++j) {
          places.merge(j, j - 1, config.min_separation, config.max_visit_span);
        }
      }
    }
  }
  auto& result = out.accepted;
  result.kept.assign(alignments.size(), false);
  result.retained_count.assign(alignments.size(), 0);
  for (std::size_t k = 0; k < alignments.size(); ++k) {
    const auto& a = alignments[k];
    for (std::size_t p = 0; p < a.pairs.size(); ++p) result.retained_count[k] += accepted[k][p] ? 1 : 0;
    result.kept[k] = result.retained_count[k] > 0 && static_cast<double>(result.retained_count[k]) >=
                                                         min_kept_fraction * static_cast<double>(a.pairs.size());
    auto gap = skipped[k].begin();  // in increasing i, like the pairs
    for (std::size_t p = 0; p < a.pairs.size(); ++p) {
      for (; gap != skipped[k].end() && gap->first < a.pairs[p].first; ++gap) {
        result.pairs.push_back({gap->first, gap->second, k, a.score});
      }
      if (accepted[k][p]) result.pairs.push_back({a.pairs[p].first, a.pairs[p].second, k, a.score});
    }
  }
  std::vector<PlaceLabel> root_label(images, -1);
  out.labels.resize(images);
  PlaceLabel next = 0;
  for (std::size_t k = 0; k < images; ++k) {
    const std::size_t root = places.find(k);
    if (root_label[root] < 0) root_label[root] = next++;
    out.labels[k] = root_label[root];
  }
  return out;
}

}  // namespace seqtopo::mapping
