#include <gtest/gtest.h>

#include <cstdio>
#include <stdexcept>

#include "seqtopo/trajectory/ekf_map.hpp"
#include "seqtopo/trajectory/trajectory_error.hpp"
#include "trajectory/square_loop.hpp"

namespace seqtopo::trajectory {
namespace {

TEST(EkfMap, WithoutRevisitsTheMapIsTheOdometry) {
  const auto w = test_support::square_loop();
  std::vector<int> unique(w.odometry.size());
  for (std::size_t i = 0; i < unique.size(); ++i) unique[i] = static_cast<int>(i);
  const EkfResult r = ekf_map(w.odometry, unique);
  test_support::expect_same_poses(r.robot, w.odometry, 1e-9);
  test_support::expect_same_poses(r.images, w.odometry, 1e-9);
  EXPECT_EQ(r.landmarks.size(), w.odometry.size());

  // Negative labels are "no place": nothing is observed either.
  const EkfResult none = ekf_map(w.odometry, std::vector<int>(w.odometry.size(), -1));
  test_support::expect_same_poses(none.robot, w.odometry, 1e-9);
  EXPECT_TRUE(none.landmarks.empty());
}

TEST(EkfMap, SquareLoopTwiceCorrectsTheDrift) {
  for (std::uint32_t seed : {7U, 1U, 4U}) {
    SCOPED_TRACE(seed);
    const auto w = test_support::square_loop(seed);
    const EkfResult r = ekf_map(w.odometry, w.labels);
    ASSERT_EQ(r.robot.size(), w.truth.size());
    ASSERT_EQ(r.images.size(), w.truth.size());
    EXPECT_EQ(r.landmarks.size(), 80U);
    const double ate_odometry = absolute_trajectory_error(w.odometry, w.truth);
    const double ate_filtered = absolute_trajectory_error(r.robot, w.truth);
    const double ate_images = absolute_trajectory_error(r.images, w.truth);
    std::printf("square loop (seed %u) ATE [m]: odometry %.3f, EKF filtered robot %.3f, EKF images %.3f\n", seed,
                ate_odometry, ate_filtered, ate_images);
    EXPECT_GT(ate_odometry, 1.0);  // the test only means something if the odometry is clearly wrong
    EXPECT_LT(ate_filtered, ate_odometry);
    EXPECT_LT(ate_images, 0.5 * ate_odometry);
    // Images of the same place share its landmark.
    for (std::size_t k = 80; k < w.truth.size(); ++k) {
      EXPECT_DOUBLE_EQ(r.images[k].x, r.images[k - 80].x);
      EXPECT_DOUBLE_EQ(r.images[k].y, r.images[k - 80].y);
    }
  }
}

TEST(EkfMap, Deterministic) {
  const auto w = test_support::square_loop(11);
  const EkfResult a = ekf_map(w.odometry, w.labels);
  const EkfResult b = ekf_map(w.odometry, w.labels);
  test_support::expect_same_poses(a.robot, b.robot, 0.0);
}

TEST(EkfMap, EmptyInputAndMisuse) {
  EXPECT_TRUE(ekf_map({}, {}).robot.empty());
  EXPECT_THROW(ekf_map({{0, 0, 0}}, {}), std::invalid_argument);
  EkfConfig bad;
  bad.observation_sigma = 0;
  EXPECT_THROW(ekf_map({{0, 0, 0}}, {0}, bad), std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::trajectory
