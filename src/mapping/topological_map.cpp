#include "seqtopo/mapping/topological_map.hpp"

#include <algorithm>
#include <cstdint>
#include <map>
#include <set>
#include <stdexcept>

namespace seqtopo::mapping {
namespace {

// Junction places closer than `distance` edges to one another, grouped by single linkage: one junction each.
// Returns per group {the representative (its graph centre among the group, the smallest label of equals)},
// {the group, sorted}, ordered by representative.
std::vector<std::pair<PlaceLabel, std::vector<PlaceLabel>>> junction_regions(
    const std::vector<std::set<PlaceLabel>>& adjacency, const std::set<PlaceLabel>& junctions, std::size_t distance) {
  // Distances from each junction to the junctions within `distance` edges (breadth first, bounded).
  std::map<PlaceLabel, std::map<PlaceLabel, std::size_t>> near;
  for (PlaceLabel j : junctions) {
    std::map<PlaceLabel, std::size_t> seen{{j, 0}};
    std::vector<PlaceLabel> frontier{j};
    for (std::size_t d = 1; d <= distance && !frontier.empty(); ++d) {
      std::vector<PlaceLabel> next;
      for (PlaceLabel p : frontier) {
        for (PlaceLabel q : adjacency[static_cast<std::size_t>(p)]) {
          if (seen.emplace(q, d).second) next.push_back(q);
        }
      }
      frontier = std::move(next);
    }
    for (const auto& [p, d] : seen) {
      if (junctions.count(p)) near[j][p] = d;
    }
  }
  std::map<PlaceLabel, PlaceLabel> group;  // junction -> smallest junction of its group
  const auto root = [&](PlaceLabel x) {
    while (group.at(x) != x) x = group.at(x);
    return x;
  };
  for (PlaceLabel j : junctions) group[j] = j;
  for (const auto& [j, others] : near) {
    for (const auto& [p, d] : others) {
      const PlaceLabel a = root(j), b = root(p);
      if (a != b) group[std::max(a, b)] = std::min(a, b);
    }
  }
  std::map<PlaceLabel, std::vector<PlaceLabel>> members;
  for (PlaceLabel j : junctions) members[root(j)].push_back(j);
  std::vector<std::pair<PlaceLabel, std::vector<PlaceLabel>>> out;
  for (auto& [r, places] : members) {
    // The centre: the smallest largest distance to the other members (members beyond `distance` of it, in a
    // chain, count as farther than any member within it).
    PlaceLabel centre = places.front();
    std::size_t best = SIZE_MAX;
    for (PlaceLabel c : places) {
      std::size_t eccentricity = 0;
      for (PlaceLabel p : places) {
        const auto it = near[c].find(p);
        eccentricity = std::max(eccentricity, it == near[c].end() ? distance + 1 : it->second);
      }
      if (eccentricity < best) best = eccentricity, centre = c;
    }
    out.emplace_back(centre, std::move(places));
  }
  std::sort(out.begin(), out.end());
  return out;
}

using Adjacency = std::vector<std::set<PlaceLabel>>;

// Whether images a and a + 1 are consecutive in one session.
bool joined(const std::set<std::size_t>& session_starts, long a) {
  return !session_starts.count(static_cast<std::size_t>(a + 1));
}

// Whether the two traversals of an alignment come from (or go to) different places at pair (i, j).
// step = -1 looks at predecessors, +1 at successors, along the alignment's own direction.
bool diverges(const std::vector<PlaceLabel>& labels, std::size_t i, std::size_t j, int step, align::Direction direction,
              std::size_t u_turn_separation, const std::set<std::size_t>& session_starts) {
  const auto n = static_cast<long>(labels.size());
  const std::size_t separation = i > j ? i - j : j - i;
  if (direction == align::Direction::reverse && separation <= u_turn_separation) return false;
  // The place each traversal came from (or goes to): the first image along it in another place than its own (a
  // slow pass holds a place for a few images). None before the session's end: the path starts or stops there.
  const auto neighbour = [&](std::size_t x, int d) -> long {
    long at = static_cast<long>(x);
    while (true) {
      const long next = at + d;
      if (next < 0 || next >= n || !joined(session_starts, std::min(next, at))) return -1;
      at = next;
      if (labels[static_cast<std::size_t>(at)] != labels[x]) return at;
    }
  };
  const long ni = neighbour(i, step);
  const long nj = neighbour(j, direction == align::Direction::forward ? step : -step);
  if (ni < 0 || nj < 0) return false;
  return labels[static_cast<std::size_t>(ni)] != labels[static_cast<std::size_t>(nj)];
}

std::vector<PathSegment> collapse_segments(const Adjacency& adjacency, const std::set<PlaceLabel>& stops) {
  const auto count = static_cast<PlaceLabel>(adjacency.size());
  std::set<std::pair<PlaceLabel, PlaceLabel>> walked;  // directed edges already part of a segment
  std::vector<PathSegment> segments;
  auto walk = [&](PlaceLabel from, PlaceLabel next) {
    PathSegment s{{from}};
    PlaceLabel prev = from, cur = next;
    walked.insert({from, next});
    while (true) {
      s.places.push_back(cur);
      if (stops.count(cur) || cur == from) break;
      // a non-stop place has exactly two neighbours: continue through the other one
      const PlaceLabel other = *adjacency[cur].begin() == prev ? *adjacency[cur].rbegin() : *adjacency[cur].begin();
      walked.insert({cur, other});
      prev = cur;
      cur = other;
    }
    walked.insert({cur, prev});
    segments.push_back(std::move(s));
  };
  for (PlaceLabel p = 0; p < count; ++p) {
    if (!stops.count(p)) continue;
    if (adjacency[p].empty()) segments.push_back({{p}});
    for (PlaceLabel q : adjacency[p]) {
      if (!walked.count({p, q})) walk(p, q);
    }
  }
  // Loops made only of degree-2 places: start each at its smallest place.
  for (PlaceLabel p = 0; p < count; ++p) {
    if (stops.count(p) || adjacency[p].size() != 2) continue;
    const PlaceLabel q = *adjacency[p].begin();
    if (!walked.count({p, q}) && !walked.count({q, p})) walk(p, q);
  }
  std::sort(segments.begin(), segments.end(),
            [](const PathSegment& a, const PathSegment& b) { return a.places < b.places; });
  return segments;
}

}  // namespace

TopologicalMap build_topology(const std::vector<PlaceLabel>& labels,
                              const std::vector<align::LocalAlignment>& alignments, const PruningResult& pruning,
                              const TopologyConfig& config) {
  if (pruning.kept.size() != alignments.size())
    throw std::invalid_argument("pruning result does not match the alignments");
  TopologicalMap map;
  map.labels = labels;
  PlaceLabel count = 0;
  for (PlaceLabel l : labels) {
    if (l < 0) throw std::invalid_argument("place labels must be >= 0");
    count = std::max(count, l + 1);
  }
  map.places.resize(static_cast<std::size_t>(count));
  for (PlaceLabel p = 0; p < count; ++p) map.places[p].id = p;
  for (std::size_t k = 0; k < labels.size(); ++k) map.places[labels[k]].images.push_back(k);

  const std::set<std::size_t> session_starts(config.session_starts.begin(), config.session_starts.end());
  Adjacency adjacency(static_cast<std::size_t>(count));
  std::map<std::pair<PlaceLabel, PlaceLabel>, std::size_t> traversals;
  for (std::size_t k = 1; k < labels.size(); ++k) {
    const PlaceLabel a = labels[k - 1], b = labels[k];
    if (a == b || session_starts.count(k)) continue;
    adjacency[a].insert(b);
    adjacency[b].insert(a);
    ++traversals[std::minmax(a, b)];
  }
  if (config.reduce_transitive) {
    // Decided on the unreduced graph, then removed together: what is removed does not depend on the order.
    const auto count_of = [&](PlaceLabel a, PlaceLabel b) { return traversals.at(std::minmax(a, b)); };
    std::vector<std::pair<PlaceLabel, PlaceLabel>> redundant;
    for (const auto& [edge, n] : traversals) {
      const auto [p, q] = edge;
      for (PlaceLabel x : adjacency[p]) {
        if (x != q && adjacency[q].count(x) && count_of(p, x) > n && count_of(x, q) > n) {
          redundant.push_back(edge);
          break;
        }
      }
    }
    for (auto [p, q] : redundant) {
      adjacency[p].erase(q);
      adjacency[q].erase(p);
    }
  }
  for (PlaceLabel p = 0; p < count; ++p) {
    for (PlaceLabel q : adjacency[p]) {
      if (p < q) map.edges.emplace_back(p, q);
    }
  }

  std::set<PlaceLabel> junctions;
  for (PlaceLabel p = 0; p < count; ++p) {
    if (adjacency[p].size() >= 3) junctions.insert(p);
  }
  // First and last retained pair of each kept alignment.
  std::map<std::size_t, std::pair<RetainedPair, RetainedPair>> ends;
  for (const auto& pair : pruning.pairs) {
    auto it = ends.find(pair.alignment);
    if (it == ends.end()) {
      ends.emplace(pair.alignment, std::make_pair(pair, pair));
    } else {
      if (pair.i < it->second.first.i) it->second.first = pair;
      if (pair.i > it->second.second.i) it->second.second = pair;
    }
  }
  for (const auto& [k, first_last] : ends) {
    const auto direction = alignments[k].direction;
    const auto& [first, last] = first_last;
    if (diverges(labels, first.i, first.j, -1, direction, config.u_turn_separation, session_starts)) {
      junctions.insert(labels[first.i]);
    }
    if (diverges(labels, last.i, last.j, +1, direction, config.u_turn_separation, session_starts)) {
      junctions.insert(labels[last.i]);
    }
  }
  std::set<PlaceLabel> stops = junctions;
  for (const auto& region : junction_regions(adjacency, junctions, config.junction_region)) {
    map.junctions.push_back(region.first);
    map.junction_regions.push_back(region.second);
  }
  for (PlaceLabel p = 0; p < count; ++p) {
    if (adjacency[p].size() != 2) stops.insert(p);
  }
  map.segments = collapse_segments(adjacency, stops);
  describe_junctions(map, alignments, pruning, config);
  return map;
}

void describe_junctions(TopologicalMap& map, const std::vector<align::LocalAlignment>& alignments,
                        const PruningResult& pruning, const TopologyConfig& config) {
  const auto& labels = map.labels;
  const std::set<std::size_t> starts(config.session_starts.begin(), config.session_starts.end());
  const auto session_of = [&](std::size_t k) {
    return static_cast<std::size_t>(std::distance(starts.begin(), starts.upper_bound(k)));
  };
  std::map<PlaceLabel, std::size_t> index;
  map.junction_evidence.assign(map.junctions.size(), {});
  for (std::size_t k = 0; k < map.junctions.size(); ++k) {
    map.junction_evidence[k].place = map.junctions[k];
    map.junction_evidence[k].region =
        k < map.junction_regions.size() ? map.junction_regions[k] : std::vector<PlaceLabel>{map.junctions[k]};
    for (PlaceLabel p : map.junction_evidence[k].region) index[p] = k;
  }
  // Every place of a junction's region counts as the junction; its branches lead out of the region.
  std::vector<std::set<PlaceLabel>> branches(map.junctions.size());
  for (auto [p, q] : map.edges) {
    const auto ip = index.find(p), iq = index.find(q);
    if (ip != index.end() && (iq == index.end() || iq->second != ip->second)) branches[ip->second].insert(q);
    if (iq != index.end() && (ip == index.end() || ip->second != iq->second)) branches[iq->second].insert(p);
  }
  // Passes: maximal runs of consecutive images of one session in one junction's region.
  const auto junction_of = [&](std::size_t image) {
    const auto it = index.find(labels[image]);
    return it == index.end() ? SIZE_MAX : it->second;
  };
  for (std::size_t b = 0; b < labels.size();) {
    const std::size_t k = junction_of(b);
    std::size_t e = b + 1;
    while (e < labels.size() && k != SIZE_MAX && junction_of(e) == k && !starts.count(e)) ++e;
    if (k != SIZE_MAX) {
      JunctionPass pass{b, e - 1, -1, -1, session_of(b)};
      if (b > 0 && !starts.count(b)) pass.from = labels[b - 1];
      if (e < labels.size() && !starts.count(e)) pass.to = labels[e];
      map.junction_evidence[k].passes.push_back(pass);
    }
    b = e;
  }
  std::vector<std::set<std::size_t>> images(map.junctions.size()), kept(map.junctions.size());
  for (std::size_t k = 0; k < map.junctions.size(); ++k) {
    auto& j = map.junction_evidence[k];
    j.branches.assign(branches[k].begin(), branches[k].end());
    j.by_degree = j.branches.size() >= 3;
    std::map<PlaceLabel, std::size_t> arrivals, departures;
    for (const auto& pass : j.passes) {
      ++arrivals[pass.from];
      ++departures[pass.to];
    }
    std::set<std::size_t> sessions;
    for (const auto& pass : j.passes) {
      sessions.insert(pass.session);
      // A pass whose neighbour no other pass shares joins (or leaves) the others here.
      if (pass.from >= 0 && arrivals[pass.from] == 1 && j.passes.size() > 1) images[k].insert(pass.first_image);
      if (pass.to >= 0 && departures[pass.to] == 1 && j.passes.size() > 1) images[k].insert(pass.last_image);
    }
    j.sessions.assign(sessions.begin(), sessions.end());
  }
  for (const auto& pair : pruning.pairs) {
    for (std::size_t x : {pair.i, pair.j}) {
      if (auto it = index.find(labels[x]); it != index.end()) {
        auto& c = map.junction_evidence[it->second].confidence;
        c = std::max(c, pair.confidence);
      }
    }
  }
  for (const auto& [a, first_last] : retained_ends(pruning)) {
    const auto direction = alignments[a].direction;
    for (const auto& [pair, step] : {std::pair{first_last.first, -1}, std::pair{first_last.second, 1}}) {
      const auto it = index.find(labels[pair.i]);
      if (it == index.end() || labels[pair.j] != labels[pair.i]) continue;
      kept[it->second].insert(a);
      if (diverges(labels, pair.i, pair.j, step, direction, config.u_turn_separation, starts)) {
        map.junction_evidence[it->second].by_alignment = true;
        images[it->second].insert(pair.i);
        images[it->second].insert(pair.j);
      }
    }
  }
  for (std::size_t k = 0; k < map.junctions.size(); ++k) {
    map.junction_evidence[k].images.assign(images[k].begin(), images[k].end());
    map.junction_evidence[k].alignments.assign(kept[k].begin(), kept[k].end());
  }
}

}  // namespace seqtopo::mapping
