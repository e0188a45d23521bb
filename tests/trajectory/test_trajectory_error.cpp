#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "seqtopo/trajectory/trajectory_error.hpp"
#include "trajectory/square_loop.hpp"

namespace seqtopo::trajectory {
namespace {

TEST(TrajectoryError, ZeroForIdenticalTrajectories) {
  const auto w = test_support::square_loop();
  EXPECT_NEAR(absolute_trajectory_error(w.truth, w.truth), 0.0, 1e-12);
  EXPECT_NEAR(absolute_trajectory_error(w.odometry, w.odometry), 0.0, 1e-12);
}

TEST(TrajectoryError, InvariantToARigidTransformOfTheEstimate) {
  const auto w = test_support::square_loop();
  const double ate = absolute_trajectory_error(w.odometry, w.truth);
  EXPECT_GT(ate, 0.1);
  const Pose2 t{-12.5, 40.25, 2.2};
  std::vector<Pose2> moved;
  for (const auto& p : w.odometry) moved.push_back(compose(t, p));
  EXPECT_NEAR(absolute_trajectory_error(moved, w.truth), ate, 1e-9);
  std::vector<Pose2> truth_moved;
  for (const auto& p : w.truth) truth_moved.push_back(compose(t, p));
  EXPECT_NEAR(absolute_trajectory_error(truth_moved, w.truth), 0.0, 1e-9);
  // The recovered transform maps the moved truth back onto the truth.
  const RigidAlignment a = align_trajectory(truth_moved, w.truth);
  const Pose2 inverse = between(t, Pose2{});
  EXPECT_NEAR(a.transform.x, inverse.x, 1e-9);
  EXPECT_NEAR(a.transform.y, inverse.y, 1e-9);
  EXPECT_NEAR(wrap_angle(a.transform.theta - inverse.theta), 0.0, 1e-9);
}

TEST(TrajectoryError, NoScaleIsFitted) {
  // A trajectory twice as large cannot be aligned away: it keeps an error.
  std::vector<Pose2> truth{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  std::vector<Pose2> big;
  for (const auto& p : truth) big.push_back({2 * p.x, 2 * p.y, 0});
  // Centred corners are (+-0.5, +-0.5) vs (+-1, +-1): each is off by sqrt(0.5) after the best fit.
  EXPECT_NEAR(absolute_trajectory_error(big, truth), std::sqrt(0.5), 1e-12);
}

TEST(TrajectoryError, KnownValueForAPureOffsetNoise) {
  // Alternating +-0.1 m in y on a straight line: translation cannot remove it, rotation barely helps.
  std::vector<Pose2> truth, est;
  for (int i = 0; i < 4; ++i) {
    truth.push_back({static_cast<double>(i), 0, 0});
    est.push_back({static_cast<double>(i), (i % 2 == 0 ? 0.1 : -0.1), 0});
  }
  const double ate = absolute_trajectory_error(est, truth);
  EXPECT_GT(ate, 0.05);
  EXPECT_LE(ate, 0.1 + 1e-12);
}

TEST(TrajectoryError, RejectsMismatchedOrEmptyInput) {
  EXPECT_THROW(absolute_trajectory_error({{0, 0, 0}}, {}), std::invalid_argument);
  EXPECT_THROW(absolute_trajectory_error({}, {}), std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::trajectory
