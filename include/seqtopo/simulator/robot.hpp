#pragma once
// The robot: a path graph it may drive on, a route through it (legs = traversals, each with its own
// path-following error and lighting), the frames recorded every `interval` metres of travel, the places
// those frames belong to, and wheel odometry with drift and noise.
#include <array>
#include <cstdint>
#include <vector>

#include "seqtopo/simulator/geometry.hpp"
#include "seqtopo/simulator/render.hpp"

namespace seqtopo::simulator {

struct PathGraph {
  std::vector<Vec2> nodes;                // [m]
  std::vector<std::array<int, 2>> edges;  // straight segments between nodes
  int add_node(Vec2 p) {
    nodes.push_back(p);
    return static_cast<int>(nodes.size()) - 1;
  }
  void add_edge(int a, int b) { edges.push_back({a, b}); }
  // Index of the edge joining a and b (either way round), or -1.
  int edge_between(int a, int b) const;
};

// How the path graph is cut into places: each node owns the stretch within junction_radius of it; the rest
// of each edge is split evenly into pieces close to place_length.
struct PlaceConfig {
  double place_length = 1.5;      // [m]
  double junction_radius = 0.75;  // [m]
};

// Place id on the path graph before compaction: nodes first, then the pieces of each edge in order.
int raw_place(const PathGraph& graph, const PlaceConfig& config, int edge, double along);

// Imperfect path following: a constant lateral offset (to the left of travel) plus a zig-zag
// (triangle wave) of the given amplitude and period along the path.
struct PathFollowing {
  double lateral_offset = 0.0;    // [m]
  double zigzag_amplitude = 0.0;  // [m]
  double zigzag_period = 4.0;     // [m] of path
};

struct RouteLeg {
  std::vector<int> nodes;  // consecutive nodes must share an edge; a leg starts where the previous ended
  PathFollowing following;
  Lighting lighting;
};

struct RouteFrame {
  Pose2 pose;        // ground truth T_world_robot
  Vec2 on_path;      // the point of the path graph the robot was following [m]
  int edge = 0;      // the edge of that point
  double along = 0;  // its distance from the edge's first node [m]
  int leg = 0;       // the traversal it belongs to
};

// Drives the route and records a frame every `interval` metres of actual travel (zig-zags travel
// further, so they record more frames). Throws std::invalid_argument on a broken route.
std::vector<RouteFrame> follow_route(const PathGraph& graph, const std::vector<RouteLeg>& legs, double interval);

// Odometry error model: a scale error and heading drift (systematic) plus noise growing with the
// square root of the distance travelled.
struct OdometryNoise {
  double scale_error = 0.0;        // fraction of distance (0.01 = odometry reads 1 % long)
  double heading_drift = 0.0;      // [rad/m]
  double translation_sigma = 0.0;  // [m/sqrt(m)]
  double rotation_sigma = 0.0;     // [rad/sqrt(m)]
};

// Motion between consecutive poses in the frame of the earlier one (dx, dy, dtheta).
std::vector<Pose2> pose_increments(const std::vector<Pose2>& poses);
// Chains increments starting from `start`; integrate(start, pose_increments(p)) == p up to rounding.
std::vector<Pose2> integrate_increments(const Pose2& start, const std::vector<Pose2>& increments);
// Cumulative odometry for the ground-truth poses, starting at the true first pose.
std::vector<Pose2> simulate_odometry(const std::vector<Pose2>& truth, const OdometryNoise& noise, std::uint64_t seed);

}  // namespace seqtopo::simulator
