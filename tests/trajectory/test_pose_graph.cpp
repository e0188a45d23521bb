#include <gtest/gtest.h>

#include <cstdio>
#include <stdexcept>

#include "seqtopo/trajectory/ekf_map.hpp"
#include "seqtopo/trajectory/pose_graph.hpp"
#include "seqtopo/trajectory/trajectory_error.hpp"
#include "trajectory/square_loop.hpp"

namespace seqtopo::trajectory {
namespace {

TEST(PoseGraph, WithoutLoopPairsTheGraphIsTheOdometry) {
  const auto w = test_support::square_loop();
  test_support::expect_same_poses(pose_graph(w.odometry, {}), w.odometry, 1e-9);
}

TEST(PoseGraph, SquareLoopTwiceCorrectsTheDrift) {
  for (std::uint32_t seed : {7U, 1U, 4U}) {
    SCOPED_TRACE(seed);
    const auto w = test_support::square_loop(seed);
    const std::vector<Pose2> corrected = pose_graph(w.odometry, w.pairs);
    ASSERT_EQ(corrected.size(), w.truth.size());
    const double ate_odometry = absolute_trajectory_error(w.odometry, w.truth);
    const double ate_graph = absolute_trajectory_error(corrected, w.truth);
    const double ate_ekf = absolute_trajectory_error(ekf_map(w.odometry, w.labels).images, w.truth);
    std::printf("square loop (seed %u) ATE [m]: odometry %.3f, EKF images %.3f, pose graph %.3f\n", seed, ate_odometry,
                ate_ekf, ate_graph);
    EXPECT_GT(ate_odometry, 1.0);
    EXPECT_LT(ate_graph, 0.5 * ate_odometry);
    // The first pose anchors the map frame.
    EXPECT_DOUBLE_EQ(corrected[0].x, w.odometry[0].x);
    EXPECT_DOUBLE_EQ(corrected[0].y, w.odometry[0].y);
    EXPECT_DOUBLE_EQ(corrected[0].theta, w.odometry[0].theta);
  }
}

TEST(PoseGraph, RobustLossSurvivesAWrongPair) {
  auto w = test_support::square_loop();
  const double clean = absolute_trajectory_error(pose_graph(w.odometry, w.pairs), w.truth);
  // Opposite corners of the square wrongly judged the same place.
  w.pairs.emplace_back(130, 20);
  w.pairs.emplace_back(131, 21);
  const double with_wrong = absolute_trajectory_error(pose_graph(w.odometry, w.pairs), w.truth);
  PoseGraphConfig least_squares;
  least_squares.loss = "none";
  const double without_loss = absolute_trajectory_error(pose_graph(w.odometry, w.pairs, least_squares), w.truth);
  std::printf("pose graph ATE [m]: clean %.3f, two wrong pairs %.3f (%.3f without a robust loss)\n", clean, with_wrong,
              without_loss);
  EXPECT_LT(with_wrong, 0.5 * absolute_trajectory_error(w.odometry, w.truth));
  EXPECT_LT(with_wrong, without_loss);
}

TEST(PoseGraph, DeterministicAndLossesSelectable) {
  const auto w = test_support::square_loop(11);
  test_support::expect_same_poses(pose_graph(w.odometry, w.pairs), pose_graph(w.odometry, w.pairs), 0.0);
  for (const char* loss : {"none", "huber", "cauchy"}) {
    PoseGraphConfig c;
    c.loss = loss;
    EXPECT_LT(absolute_trajectory_error(pose_graph(w.odometry, w.pairs, c), w.truth),
              absolute_trajectory_error(w.odometry, w.truth))
        << loss;
  }
}

TEST(PoseGraph, Misuse) {
  const std::vector<Pose2> odo{{0, 0, 0}, {1, 0, 0}};
  EXPECT_THROW(pose_graph(odo, {{0, 2}}), std::invalid_argument);
  PoseGraphConfig c;
  c.loss = "tukey-ish";
  EXPECT_THROW(pose_graph(odo, {}, c), std::invalid_argument);
  c = {};
  c.loop_sigma_xy = -1;
  EXPECT_THROW(pose_graph(odo, {}, c), std::invalid_argument);
  EXPECT_TRUE(pose_graph({}, {}).empty());
  test_support::expect_same_poses(pose_graph({{1, 2, 3}}, {{0, 0}}), {{1, 2, 3}}, 0.0);
}

}  // namespace
}  // namespace seqtopo::trajectory
