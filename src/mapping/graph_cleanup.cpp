#include "seqtopo/mapping/graph_cleanup.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

namespace seqtopo::mapping {
namespace {

// Session boundaries of the images: begin(k) is the first image of k's session, end(k) one past its last.
class Sessions {
 public:
  Sessions(std::size_t images, const std::vector<std::size_t>& starts) : starts_(starts.begin(), starts.end()) {
    starts_.insert(0);
    starts_.insert(images);
  }
  std::size_t begin(std::size_t k) const { return *std::prev(starts_.upper_bound(k)); }
  std::size_t end(std::size_t k) const { return *starts_.upper_bound(k); }
  bool joined(std::size_t k) const { return !starts_.count(k + 1); }  // k and k + 1 taken one after the other

 private:
  std::set<std::size_t> starts_;
};

// The place graph of the current labels: neighbours, images, passes per place, traversals per edge.
struct Graph {
  std::vector<std::set<PlaceLabel>> neighbours;
  std::vector<std::vector<std::size_t>> images;
  std::vector<std::size_t> passes;
};

Graph graph_of(const std::vector<PlaceLabel>& labels, const Sessions& sessions, std::size_t min_separation) {
  PlaceLabel count = 0;
  for (PlaceLabel l : labels) count = std::max(count, l + 1);
  Graph g;
  g.neighbours.resize(static_cast<std::size_t>(count));
  g.images.resize(static_cast<std::size_t>(count));
  g.passes.assign(static_cast<std::size_t>(count), 0);
  for (std::size_t k = 0; k < labels.size(); ++k) {
    g.images[labels[k]].push_back(k);
    if (k + 1 < labels.size() && sessions.joined(k) && labels[k] != labels[k + 1]) {
      g.neighbours[labels[k]].insert(labels[k + 1]);
      g.neighbours[labels[k + 1]].insert(labels[k]);
    }
  }
  for (std::size_t p = 0; p < g.images.size(); ++p) {
    const auto& m = g.images[p];
    for (std::size_t k = 0; k < m.size(); ++k) g.passes[p] += (k == 0 || m[k] - m[k - 1] >= min_separation) ? 1 : 0;
  }
  return g;
}

std::vector<PlaceLabel> renumbered(const std::vector<PlaceLabel>& labels) {
  std::map<PlaceLabel, PlaceLabel> to;
  std::vector<PlaceLabel> out(labels.size());
  for (std::size_t k = 0; k < labels.size(); ++k) {
    auto it = to.try_emplace(labels[k], static_cast<PlaceLabel>(to.size())).first;
    out[k] = it->second;
  }
  return out;
}

// Rule 1: extends kept alignments whose one traversal ends within the overhang allowed of its session's end.
std::size_t extend_overhangs(std::vector<PlaceLabel>& labels, const std::vector<align::LocalAlignment>& alignments,
                             const PruningResult& pruning, const GraphCleanupConfig& config, const Sessions& sessions) {
  const auto ends = retained_ends(pruning);  // first and last accepted pair
  std::map<std::size_t, std::size_t> accepted;
  for (const auto& pair : pruning.pairs) ++accepted[pair.alignment];
  // Images beyond x in direction d (+1 / -1) within x's session.
  auto hang = [&](std::size_t x, int d) { return d > 0 ? sessions.end(x) - 1 - x : x - sessions.begin(x); };
  std::size_t moved = 0;
  Graph g = graph_of(labels, sessions, config.min_separation);
  for (const auto& [k, first_last] : ends) {
    if (!pruning.kept[k]) continue;
    const int dj = alignments[k].direction == align::Direction::forward ? 1 : -1;
    const double allowed = config.hang_fraction * static_cast<double>(accepted[k]);
    for (const auto& [pair, di] : {std::pair{first_last.first, -1}, std::pair{first_last.second, 1}}) {
      const int dpj = di * dj;
      const std::size_t hi = hang(pair.i, di), hj = hang(pair.j, dpj);
      const std::size_t steps = std::min(hi, hj);
      if (steps == 0 || static_cast<double>(steps) > allowed) continue;
      const bool short_i = hi <= hj;  // the side that reaches its session's end; on a tie the later image
      for (std::size_t s = 1; s <= steps; ++s) {
        const auto xi = static_cast<std::size_t>(static_cast<long>(pair.i) + di * static_cast<long>(s));
        const auto xj = static_cast<std::size_t>(static_cast<long>(pair.j) + dpj * static_cast<long>(s));
        const std::size_t from = short_i ? xi : xj, to = short_i ? xj : xi;
        // Only an image no revisit has merged yet: its place holds its own pass alone.
        if (g.passes[labels[from]] != 1 || labels[from] == labels[to]) break;
        labels[from] = labels[to];
        ++moved;
      }
      g = graph_of(labels, sessions, config.min_separation);
    }
  }
  return moved;
}

// Rule 2: dead-end chains of single-pass places with few images join the place they hang from.
std::size_t clip_tips(std::vector<PlaceLabel>& labels, const GraphCleanupConfig& config, const Sessions& sessions) {
  std::size_t moved = 0;
  for (bool changed = true; changed;) {
    changed = false;
    const Graph g = graph_of(labels, sessions, config.min_separation);
    for (std::size_t t = 0; t < g.neighbours.size() && !changed; ++t) {
      if (g.neighbours[t].size() != 1) continue;
      std::vector<PlaceLabel> chain{static_cast<PlaceLabel>(t)};
      std::size_t frames = g.images[t].size();
      PlaceLabel prev = static_cast<PlaceLabel>(t), cur = *g.neighbours[t].begin();
      while (g.neighbours[cur].size() == 2 && frames <= config.max_tip_frames) {
        chain.push_back(cur);
        frames += g.images[cur].size();
        const PlaceLabel next =
            *g.neighbours[cur].begin() == prev ? *g.neighbours[cur].rbegin() : *g.neighbours[cur].begin();
        prev = cur;
        cur = next;
      }
      if (g.neighbours[cur].size() < 3 || frames > config.max_tip_frames) continue;
      if (std::any_of(chain.begin(), chain.end(), [&](PlaceLabel p) { return g.passes[p] != 1; })) continue;
      for (PlaceLabel p : chain) {
        for (std::size_t k : g.images[p]) labels[k] = cur;
        moved += g.images[p].size();
      }
      changed = true;
    }
  }
  return moved;
}

// Rule 3: bubbles. One round pops every bubble whose places no other pop of the round touched.
std::size_t pop_bubbles(std::vector<PlaceLabel>& labels, const PruningResult& pruning, const GraphCleanupConfig& config,
                        const Sessions& sessions) {
  // The alignments that accepted a pair with each image.
  std::vector<std::set<std::size_t>> paired(labels.size());
  for (const auto& pair : pruning.pairs) {
    paired[pair.i].insert(pair.alignment);
    paired[pair.j].insert(pair.alignment);
  }
  auto spanned = [&](std::size_t before, std::size_t after) {
    return std::any_of(paired[before].begin(), paired[before].end(),
                       [&](std::size_t a) { return paired[after].count(a) > 0; });
  };
  std::size_t moved = 0;
  for (bool changed = true; changed;) {
    changed = false;
    const Graph g = graph_of(labels, sessions, config.min_separation);
    std::set<PlaceLabel> touched;
    for (std::size_t p0 = 0; p0 < g.neighbours.size(); ++p0) {
      const auto p = static_cast<PlaceLabel>(p0);
      if (g.neighbours[p].size() < 3 || touched.count(p)) continue;
      for (PlaceLabel first : g.neighbours[p]) {
        // The chain from p through places of two neighbours each.
        std::vector<PlaceLabel> chain;
        std::size_t frames = 0;
        PlaceLabel prev = p, cur = first;
        while (cur != p && g.neighbours[cur].size() == 2 && frames <= config.max_bubble_frames) {
          chain.push_back(cur);
          frames += g.images[cur].size();
          const PlaceLabel next =
              *g.neighbours[cur].begin() == prev ? *g.neighbours[cur].rbegin() : *g.neighbours[cur].begin();
          prev = cur;
          cur = next;
        }
        const PlaceLabel q = cur;
        if (chain.empty() || g.neighbours[q].size() < 2 || frames > config.max_bubble_frames) continue;
        const std::set<PlaceLabel> inner(chain.begin(), chain.end());
        if (touched.count(q) || std::any_of(chain.begin(), chain.end(), [&](PlaceLabel x) { return touched.count(x); }))
          continue;
        if (q == p) {
          // A hairpin: the chain leaves p and comes back to it, each of its places seen once. One stretch driven
          // out and back (a U-turn) whose two legs were not merged: its places become one dead end.
          if (std::any_of(chain.begin(), chain.end(), [&](PlaceLabel x) { return g.passes[x] != 1; })) continue;
          for (PlaceLabel x : chain) {
            for (std::size_t k : g.images[x]) labels[k] = chain.front();
            moved += x == chain.front() ? 0 : g.images[x].size();
          }
          touched.insert(p);
          touched.insert(chain.begin(), chain.end());
          changed = true;
          break;
        }
        // The shortest other route from p to q, of at most chain.size() + 1 edges (breadth first, smallest ids
        // first, so the route does not depend on anything but the graph).
        std::map<PlaceLabel, PlaceLabel> parent{{p, p}};
        std::vector<PlaceLabel> level{p};
        for (std::size_t depth = 0; depth <= chain.size() && !parent.count(q); ++depth) {
          std::vector<PlaceLabel> next_level;
          for (PlaceLabel x : level) {
            for (PlaceLabel y : g.neighbours[x]) {
              if (inner.count(y) || parent.count(y)) continue;
              if (x == p && y == first) continue;
              parent[y] = x;
              next_level.push_back(y);
            }
          }
          level = std::move(next_level);
        }
        if (!parent.count(q)) continue;
        std::vector<PlaceLabel> route{q};
        while (route.back() != p) route.push_back(parent[route.back()]);
        std::reverse(route.begin(), route.end());  // p ... q
        if (std::any_of(route.begin(), route.end(), [&](PlaceLabel x) { return touched.count(x); })) continue;
        // Coverage: passes of the chain's places against the other route's inner places, or the traversals of
        // the edge p - q when the route is that edge.
        std::size_t chain_passes = g.images.size(), route_passes = g.images.size();
        for (PlaceLabel x : chain) chain_passes = std::min(chain_passes, g.passes[x]);
        if (route.size() == 2) {
          route_passes = 0;
          for (std::size_t k : g.images[p]) {
            if (k > 0 && labels[k - 1] == q && sessions.joined(k - 1)) ++route_passes;
            if (k + 1 < labels.size() && labels[k + 1] == q && sessions.joined(k)) ++route_passes;
          }
        } else {
          for (std::size_t r = 1; r + 1 < route.size(); ++r) route_passes = std::min(route_passes, g.passes[route[r]]);
        }
        if (chain_passes > route_passes) continue;
        // The chain's images as runs of consecutive images, each entered from p or q and left to the other.
        std::vector<std::pair<std::size_t, std::size_t>> runs;  // [begin, end)
        bool ok = true;
        std::vector<std::size_t> images;
        for (PlaceLabel x : chain) images.insert(images.end(), g.images[x].begin(), g.images[x].end());
        std::sort(images.begin(), images.end());
        for (std::size_t k = 0; k < images.size();) {
          std::size_t e = k + 1;
          while (e < images.size() && images[e] == images[e - 1] + 1 && sessions.joined(images[e - 1])) ++e;
          const std::size_t b = images[k], last = images[e - 1];
          if (b == sessions.begin(b) || last + 1 >= sessions.end(last)) ok = false;
          runs.emplace_back(b, last + 1);
          k = e;
        }
        if (!ok) continue;
        if (chain_passes == route_passes && !config.pop_ties_by_time &&
            !std::all_of(runs.begin(), runs.end(), [&](auto run) { return spanned(run.first - 1, run.second); }))
          continue;
        if (chain_passes == route_passes && config.pop_ties_by_time) {
          // The first visit defines the places; a later pass's detour is the one merged.
          std::size_t route_first = labels.size();
          if (route.size() == 2) {
            for (std::size_t k : g.images[p]) {
              if ((k + 1 < labels.size() && labels[k + 1] == q && sessions.joined(k)) ||
                  (k > 0 && labels[k - 1] == q && sessions.joined(k - 1)))
                route_first = std::min(route_first, k);
            }
          } else {
            for (std::size_t r = 1; r + 1 < route.size(); ++r)
              route_first = std::min(route_first, g.images[route[r]].front());
          }
          if (images.front() < route_first) continue;
        }
        for (auto [b, e] : runs) {
          std::vector<PlaceLabel> r = route;
          if (labels[b - 1] == q) std::reverse(r.begin(), r.end());
          const std::size_t length = e - b, m = r.size() - 1;
          for (std::size_t t = 0; t < length; ++t) {
            // position t + 1 of length + 1 steps along the m edges of the route, rounded half down
            const std::size_t at = ((t + 1) * m * 2 + length) / (2 * (length + 1));
            labels[b + t] = r[std::min(at, m)];
          }
          moved += length;
        }
        touched.insert(route.begin(), route.end());
        touched.insert(chain.begin(), chain.end());
        changed = true;
        break;
      }
    }
  }
  return moved;
}

}  // namespace

GraphCleanup clean_graph(const std::vector<PlaceLabel>& labels, const std::vector<align::LocalAlignment>& alignments,
                         const PruningResult& pruning, const GraphCleanupConfig& config) {
  if (pruning.kept.size() != alignments.size())
    throw std::invalid_argument("pruning result does not match the alignments");
  for (const auto& pair : pruning.pairs) {
    if (pair.i >= labels.size() || pair.j >= labels.size() || pair.alignment >= alignments.size())
      throw std::invalid_argument("a retained pair lies outside the images or the alignments");
  }
  for (PlaceLabel l : labels) {
    if (l < 0) throw std::invalid_argument("place labels must be >= 0");
  }
  const Sessions sessions(labels.size(), config.session_starts);
  GraphCleanup out;
  std::vector<PlaceLabel> current = labels;
  out.extended_images = extend_overhangs(current, alignments, pruning, config, sessions);
  out.clipped_images = clip_tips(current, config, sessions);
  out.popped_images = pop_bubbles(current, pruning, config, sessions);
  out.labels = renumbered(current);
  return out;
}

}  // namespace seqtopo::mapping
