// Route following, places and odometry.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "seqtopo/simulator/random.hpp"
#include "seqtopo/simulator/robot.hpp"

namespace seqtopo::simulator {
namespace {

// A 10 x 6 m rectangle with a tail: 0 (tail end) - 1 - 2 - 3 - 4 - 1.
PathGraph loop_with_tail() {
  PathGraph g;
  for (Vec2 p : {Vec2{-5, 0}, Vec2{0, 0}, Vec2{10, 0}, Vec2{10, 6}, Vec2{0, 6}}) g.add_node(p);
  g.add_edge(0, 1);
  g.add_edge(1, 2);
  g.add_edge(2, 3);
  g.add_edge(3, 4);
  g.add_edge(4, 1);
  return g;
}

std::vector<RouteLeg> twice_round(PathFollowing second = {}) {
  RouteLeg a, b;
  a.nodes = {0, 1, 2, 3, 4, 1};
  b.nodes = {1, 2, 3, 4, 1, 0};
  b.following = second;
  return {a, b};
}

TEST(Route, FramesAreOneIntervalApartAlongThePath) {
  const auto frames = follow_route(loop_with_tail(), twice_round(), 0.25);
  // 5 + 32 + 32 + 5 = 74 m of travel -> 297 frames (both ends included).
  EXPECT_EQ(frames.size(), 297U);
  for (std::size_t k = 1; k < frames.size(); ++k) {
    const double step = std::hypot(frames[k].pose.x - frames[k - 1].pose.x, frames[k].pose.y - frames[k - 1].pose.y);
    EXPECT_LE(step, 0.25 + 1e-9);
    EXPECT_GT(step, 0.17);                                     // only corners cut the straight-line distance short
    EXPECT_NEAR(frames[k].pose.x, frames[k].on_path.x, 1e-9);  // perfect path following
    EXPECT_NEAR(frames[k].pose.y, frames[k].on_path.y, 1e-9);
  }
  EXPECT_EQ(frames.front().leg, 0);
  EXPECT_EQ(frames.back().leg, 1);
  EXPECT_NEAR(frames.back().pose.x, -5.0, 1e-9);
  EXPECT_NEAR(frames[4].pose.theta, 0.0, 1e-12);
}

TEST(Route, ZigZagTravelsFurtherAndStaysNearThePath) {
  PathFollowing zig;
  zig.zigzag_amplitude = 0.5;
  zig.zigzag_period = 2.0;
  const auto straight = follow_route(loop_with_tail(), twice_round(), 0.25);
  const auto zigzag = follow_route(loop_with_tail(), twice_round(zig), 0.25);
  // A triangle wave of amplitude a and period P lengthens the path by sqrt(1 + (4a/P)^2) = 1.414: the
  // second leg's 37 m become 52 m, 60 more frames.
  EXPECT_GT(zigzag.size(), straight.size() + 50);
  EXPECT_LT(zigzag.size(), straight.size() + 66);
  double max_offset = 0;
  for (const auto& f : zigzag)
    max_offset = std::max(max_offset, std::hypot(f.pose.x - f.on_path.x, f.pose.y - f.on_path.y));
  EXPECT_GT(max_offset, 0.4);
  EXPECT_LE(max_offset, 0.5 + 1e-6);
}

TEST(Route, LateralOffsetShiftsToTheLeft) {
  RouteLeg leg;
  leg.nodes = {1, 2};
  leg.following.lateral_offset = 0.3;
  const auto frames = follow_route(loop_with_tail(), {leg}, 0.5);
  // Heading east, left is north: after the 1 m ramp the robot runs 0.3 m north of the path.
  EXPECT_NEAR(frames[10].pose.y, 0.3, 1e-9);
  EXPECT_NEAR(frames[10].on_path.y, 0.0, 1e-9);
}

TEST(Route, BrokenRoutesAreRejected) {
  const PathGraph g = loop_with_tail();
  RouteLeg gap;
  gap.nodes = {0, 2};  // no edge 0-2
  EXPECT_THROW(follow_route(g, {gap}, 0.25), std::invalid_argument);
  RouteLeg a, b;
  a.nodes = {0, 1};
  b.nodes = {2, 3};  // does not start where a ended
  EXPECT_THROW(follow_route(g, {a, b}, 0.25), std::invalid_argument);
  RouteLeg missing;
  missing.nodes = {0, 9};
  EXPECT_THROW(follow_route(g, {missing}, 0.25), std::invalid_argument);
  EXPECT_THROW(follow_route(g, twice_round(), 0.0), std::invalid_argument);
}

TEST(Places, RevisitsShareIdsAndNodesOwnTheirSurroundings) {
  const PathGraph g = loop_with_tail();
  PlaceConfig config;                          // 1.5 m places, 0.75 m around nodes
  EXPECT_EQ(raw_place(g, config, 1, 0.5), 1);  // near node 1 on edge 1-2
  EXPECT_EQ(raw_place(g, config, 0, 4.5), 1);  // near node 1 on edge 0-1
  EXPECT_EQ(raw_place(g, config, 4, 5.9), 1);  // near node 1 on edge 4-1
  EXPECT_EQ(raw_place(g, config, 1, 9.6), 2);
  // Edge 1-2 (10 m): 8.5 m between the node places in 6 pieces of 1.417 m, after edge 0-1's 2 pieces.
  EXPECT_EQ(raw_place(g, config, 1, 0.8), 5 + 2);
  EXPECT_EQ(raw_place(g, config, 1, 9.2), 5 + 2 + 5);
  const auto frames = follow_route(g, twice_round(), 0.25);
  // Every stretch of the loop is driven twice: the same points get the same place.
  for (std::size_t i = 0; i < frames.size(); ++i) {
    for (std::size_t j = i + 1; j < frames.size(); ++j) {
      if (std::hypot(frames[i].on_path.x - frames[j].on_path.x, frames[i].on_path.y - frames[j].on_path.y) < 1e-9) {
        EXPECT_EQ(raw_place(g, config, frames[i].edge, frames[i].along),
                  raw_place(g, config, frames[j].edge, frames[j].along));
      }
    }
  }
}

TEST(Odometry, IncrementsIntegrateBackToThePoses) {
  Rng rng(3);
  std::vector<Pose2> poses;
  for (int k = 0; k < 200; ++k) poses.push_back({rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-3, 3)});
  const auto back = integrate_increments(poses.front(), pose_increments(poses));
  ASSERT_EQ(back.size(), poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    EXPECT_NEAR(back[k].x, poses[k].x, 1e-9);
    EXPECT_NEAR(back[k].y, poses[k].y, 1e-9);
    EXPECT_NEAR(wrap_angle(back[k].theta - poses[k].theta), 0.0, 1e-12);
  }
}

std::vector<Pose2> truth() {
  PathFollowing zig;
  zig.zigzag_amplitude = 0.3;
  std::vector<Pose2> poses;
  for (const auto& f : follow_route(loop_with_tail(), twice_round(zig), 0.25)) poses.push_back(f.pose);
  return poses;
}

TEST(Odometry, WithoutNoiseItIsTheGroundTruth) {
  const auto poses = truth();
  const auto odometry = simulate_odometry(poses, {}, 11);
  ASSERT_EQ(odometry.size(), poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    EXPECT_NEAR(odometry[k].x, poses[k].x, 1e-9);
    EXPECT_NEAR(odometry[k].y, poses[k].y, 1e-9);
    EXPECT_NEAR(wrap_angle(odometry[k].theta - poses[k].theta), 0.0, 1e-9);
  }
}

TEST(Odometry, HeadingDriftAccumulatesWithDistance) {
  const auto poses = truth();
  OdometryNoise drift;
  drift.heading_drift = 0.001;  // [rad/m]
  const auto odometry = simulate_odometry(poses, drift, 11);
  double travelled = 0;
  for (std::size_t k = 1; k < poses.size(); ++k)
    travelled += std::hypot(poses[k].x - poses[k - 1].x, poses[k].y - poses[k - 1].y);
  EXPECT_NEAR(wrap_angle(odometry.back().theta - poses.back().theta), 0.001 * travelled, 1e-9);
}

TEST(Odometry, NoiseIsSeededAndGrowsWithTheRoute) {
  const auto poses = truth();
  const OdometryNoise noise{0.01, 0.002, 0.01, 0.01};
  const auto a = simulate_odometry(poses, noise, 5);
  const auto b = simulate_odometry(poses, noise, 5);
  const auto c = simulate_odometry(poses, noise, 6);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  const double early = std::hypot(a[20].x - poses[20].x, a[20].y - poses[20].y);
  const double late = std::hypot(a.back().x - poses.back().x, a.back().y - poses.back().y);
  EXPECT_GT(late, early);
  EXPECT_GT(late, 0.05);
}

}  // namespace
}  // namespace seqtopo::simulator
