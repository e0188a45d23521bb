#include "seqtopo/simulator/robot.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "seqtopo/simulator/random.hpp"

namespace seqtopo::simulator {

int PathGraph::edge_between(int a, int b) const {
  for (std::size_t e = 0; e < edges.size(); ++e) {
    if ((edges[e][0] == a && edges[e][1] == b) || (edges[e][0] == b && edges[e][1] == a)) return static_cast<int>(e);
  }
  return -1;
}

namespace {
int pieces(double length, const PlaceConfig& config) {
  const double r = std::min(config.junction_radius, length / 2);
  return std::max(1, static_cast<int>(std::lround((length - 2 * r) / config.place_length)));
}
}  // namespace

int raw_place(const PathGraph& graph, const PlaceConfig& config, int edge, double along) {
  if (edge < 0 || edge >= static_cast<int>(graph.edges.size())) throw std::invalid_argument("raw_place: no such edge");
  if (!(config.place_length > 0) || config.junction_radius < 0) {
    throw std::invalid_argument("place length must be > 0 and junction radius >= 0");
  }
  const auto& [a, b] = graph.edges[static_cast<std::size_t>(edge)];
  const double length = distance(graph.nodes[static_cast<std::size_t>(a)], graph.nodes[static_cast<std::size_t>(b)]);
  const double r = std::min(config.junction_radius, length / 2);
  // Snapped to micrometres so that a point on a place boundary gets the same place on every visit,
  // whichever way round and with whatever rounding it was reached.
  along = std::round(along * 1e6) / 1e6;
  if (along < r) return a;
  if (along > length - r) return b;
  int offset = static_cast<int>(graph.nodes.size());
  for (int e = 0; e < edge; ++e) {
    const auto& [p, q] = graph.edges[static_cast<std::size_t>(e)];
    offset +=
        pieces(distance(graph.nodes[static_cast<std::size_t>(p)], graph.nodes[static_cast<std::size_t>(q)]), config);
  }
  const int k = pieces(length, config);
  const double piece = (length - 2 * r) / k;
  return offset + std::clamp(static_cast<int>(std::floor((along - r) / piece)), 0, k - 1);
}

namespace {

struct Sample {
  Vec2 ideal;
  Vec2 tangent;
  int edge = 0;
  double along = 0;
  int leg = 0;
  double leg_s = 0;  // path length since the leg began [m]
  double leg_length = 0;
};

// Triangle wave starting at 0 and rising: 0 -> 1 -> -1 -> 0 over one period.
double triangle(double x) {
  const double f = x - std::floor(x);
  if (f < 0.25) return 4 * f;
  if (f < 0.75) return 2 - 4 * f;
  return 4 * f - 4;
}

}  // namespace

std::vector<RouteFrame> follow_route(const PathGraph& graph, const std::vector<RouteLeg>& legs, double interval) {
  if (!(interval > 0)) throw std::invalid_argument("the recording interval must be > 0");
  constexpr double ds = 0.02;  // [m] path sampling step
  std::vector<Sample> samples;
  int previous_end = -1;
  for (std::size_t l = 0; l < legs.size(); ++l) {
    const auto& nodes = legs[l].nodes;
    if (nodes.empty()) throw std::invalid_argument("route leg " + std::to_string(l) + " has no nodes");
    for (int n : nodes) {
      if (n < 0 || n >= static_cast<int>(graph.nodes.size())) {
        throw std::invalid_argument("route leg " + std::to_string(l) + " names node " + std::to_string(n) +
                                    ", which does not exist");
      }
    }
    if (previous_end >= 0 && nodes.front() != previous_end) {
      throw std::invalid_argument("route leg " + std::to_string(l) + " does not start where the previous leg ended");
    }
    previous_end = nodes.back();
    double leg_length = 0;
    for (std::size_t k = 0; k + 1 < nodes.size(); ++k) {
      leg_length += distance(graph.nodes[static_cast<std::size_t>(nodes[k])],
                             graph.nodes[static_cast<std::size_t>(nodes[k + 1])]);
    }
    double leg_s = 0;
    for (std::size_t k = 0; k + 1 < nodes.size(); ++k) {
      const int a = nodes[k], b = nodes[k + 1];
      const int e = graph.edge_between(a, b);
      if (e < 0) {
        throw std::invalid_argument("route leg " + std::to_string(l) + ": nodes " + std::to_string(a) + " and " +
                                    std::to_string(b) + " are not joined by a path");
      }
      const Vec2 pa = graph.nodes[static_cast<std::size_t>(a)], pb = graph.nodes[static_cast<std::size_t>(b)];
      const double length = distance(pa, pb);
      const Vec2 t = (1.0 / length) * (pb - pa);
      const int steps = std::max(1, static_cast<int>(std::ceil(length / ds)));
      const bool forward = graph.edges[static_cast<std::size_t>(e)][0] == a;
      for (int i = 0; i < steps; ++i) {
        const double s = length * i / steps;
        samples.push_back({pa + s * t, t, e, forward ? s : length - s, static_cast<int>(l), leg_s + s, leg_length});
      }
      leg_s += length;
    }
    if (l + 1 == legs.size() && nodes.size() > 1) {  // the route's last point
      const int a = nodes[nodes.size() - 2], b = nodes.back();
      const int e = graph.edge_between(a, b);
      const Vec2 pa = graph.nodes[static_cast<std::size_t>(a)], pb = graph.nodes[static_cast<std::size_t>(b)];
      const bool forward = graph.edges[static_cast<std::size_t>(e)][0] == a;
      const double length = distance(pa, pb);
      samples.push_back(
          {pb, (1.0 / length) * (pb - pa), e, forward ? length : 0.0, static_cast<int>(l), leg_s, leg_length});
    }
  }
  if (samples.size() < 2) throw std::invalid_argument("the route is empty: it needs at least one edge");

  // Lateral direction: the tangent averaged over +-0.5 m, so offsets turn corners smoothly.
  const std::size_t n = samples.size();
  const auto window = static_cast<std::size_t>(0.5 / ds);
  std::vector<Vec2> prefix(n + 1);
  for (std::size_t k = 0; k < n; ++k) prefix[k + 1] = prefix[k] + samples[k].tangent;
  std::vector<Vec2> actual(n);
  double previous_offset = 0;  // the previous leg's lateral offset, ramped out over 1 m
  int current_leg = -1;
  for (std::size_t k = 0; k < n; ++k) {
    const Sample& s = samples[k];
    if (s.leg != current_leg) {
      if (current_leg >= 0) previous_offset = legs[static_cast<std::size_t>(current_leg)].following.lateral_offset;
      current_leg = s.leg;
    }
    const PathFollowing& f = legs[static_cast<std::size_t>(s.leg)].following;
    const double ramp_in = std::min(1.0, s.leg_s / 1.0);
    const double ramp = std::min(ramp_in, std::max(0.0, (s.leg_length - s.leg_s) / 1.0));
    double offset = previous_offset + (f.lateral_offset - previous_offset) * ramp_in;
    if (f.zigzag_amplitude != 0 && f.zigzag_period > 0) {
      offset += f.zigzag_amplitude * std::min(ramp, 1.0) * triangle(s.leg_s / f.zigzag_period);
    }
    const std::size_t lo = k >= window ? k - window : 0, hi = std::min(n, k + window + 1);
    Vec2 t = prefix[hi] - prefix[lo];
    const double len = norm(t);
    t = len > 1e-6 ? (1.0 / len) * t : s.tangent;
    actual[k] = s.ideal + offset * Vec2{-t.y, t.x};
  }

  std::vector<RouteFrame> frames;
  double travelled = 0, next = 0;
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const double step = distance(actual[k], actual[k + 1]);
    if (step < 1e-12) continue;
    while (next <= travelled + step) {
      const double f = (next - travelled) / step;
      const std::size_t near = f < 0.5 ? k : k + 1;
      const std::size_t back = k >= 2 ? k - 2 : 0, ahead = std::min(n - 1, k + 3);
      const Vec2 heading = actual[ahead] - actual[back];
      RouteFrame frame;
      const Vec2 p = actual[k] + f * (actual[k + 1] - actual[k]);
      frame.pose = {p.x, p.y, std::atan2(heading.y, heading.x)};
      frame.on_path = samples[k].ideal + f * (samples[k + 1].ideal - samples[k].ideal);
      frame.edge = samples[near].edge;
      frame.along = samples[near].along;
      if (samples[k].edge == samples[k + 1].edge)
        frame.along = samples[k].along + f * (samples[k + 1].along - samples[k].along);
      frame.leg = samples[near].leg;
      frames.push_back(frame);
      next += interval;
    }
    travelled += step;
  }
  return frames;
}

std::vector<Pose2> pose_increments(const std::vector<Pose2>& poses) {
  std::vector<Pose2> out;
  for (std::size_t k = 1; k < poses.size(); ++k) {
    const Pose2& a = poses[k - 1];
    const Pose2& b = poses[k];
    const double c = std::cos(a.theta), s = std::sin(a.theta);
    const double dx = b.x - a.x, dy = b.y - a.y;
    out.push_back({c * dx + s * dy, -s * dx + c * dy, wrap_angle(b.theta - a.theta)});
  }
  return out;
}

std::vector<Pose2> integrate_increments(const Pose2& start, const std::vector<Pose2>& increments) {
  std::vector<Pose2> out{start};
  Pose2 p = start;
  for (const Pose2& d : increments) {
    const double c = std::cos(p.theta), s = std::sin(p.theta);
    p = {p.x + c * d.x - s * d.y, p.y + s * d.x + c * d.y, wrap_angle(p.theta + d.theta)};
    out.push_back(p);
  }
  return out;
}

std::vector<Pose2> simulate_odometry(const std::vector<Pose2>& truth, const OdometryNoise& noise, std::uint64_t seed) {
  if (truth.empty()) return {};
  std::vector<Pose2> increments = pose_increments(truth);
  for (std::size_t k = 0; k < increments.size(); ++k) {
    Pose2& d = increments[k];
    const double travelled = std::hypot(d.x, d.y);
    Rng rng(seed, hash_combine(0x0d0, k));  // per step, so a frame's noise does not depend on the others
    const double n1 = rng.normal(), n2 = rng.normal(), n3 = rng.normal();
    const double root = std::sqrt(travelled);
    d.x = d.x * (1 + noise.scale_error) + noise.translation_sigma * root * n1;
    d.y = d.y * (1 + noise.scale_error) + 0.5 * noise.translation_sigma * root * n2;
    d.theta +=
        noise.heading_drift * travelled + noise.rotation_sigma * std::sqrt(travelled + 0.3 * std::abs(d.theta)) * n3;
  }
  return integrate_increments(truth.front(), increments);
}

}  // namespace seqtopo::simulator
