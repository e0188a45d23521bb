#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "seqtopo/core/pose2.hpp"

namespace seqtopo::trajectory {
namespace {

constexpr double pi = std::numbers::pi;

TEST(Pose2, WrapAngleIntoHalfOpenRange) {
  EXPECT_DOUBLE_EQ(wrap_angle(0.0), 0.0);
  EXPECT_NEAR(wrap_angle(3 * pi / 2), -pi / 2, 1e-12);
  EXPECT_NEAR(wrap_angle(-3 * pi / 2), pi / 2, 1e-12);
  EXPECT_NEAR(wrap_angle(10 * pi + 0.25), 0.25, 1e-12);
  EXPECT_NEAR(wrap_angle(pi), -pi, 1e-12);
  for (double a = -20; a < 20; a += 0.37) {
    const double w = wrap_angle(a);
    EXPECT_GE(w, -pi);
    EXPECT_LT(w, pi);
    EXPECT_NEAR(std::remainder(a - w, 2 * pi), 0.0, 1e-9);
  }
}

TEST(Pose2, BetweenInTheFirstPosesFrame) {
  const Pose2 a{1, 2, pi / 2};
  const Pose2 b{1, 5, pi};
  const Pose2 d = between(a, b);
  // b is 3 m straight ahead of a (a faces +y) and turned left by 90 degrees.
  EXPECT_NEAR(d.x, 3, 1e-12);
  EXPECT_NEAR(d.y, 0, 1e-12);
  EXPECT_NEAR(d.theta, pi / 2, 1e-12);
}

TEST(Pose2, ComposeAndBetweenRoundTrip) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> pos(-50, 50), ang(-4, 4);
  for (int k = 0; k < 200; ++k) {
    const Pose2 a{pos(rng), pos(rng), ang(rng)};
    const Pose2 b{pos(rng), pos(rng), ang(rng)};
    const Pose2 b2 = compose(a, between(a, b));
    EXPECT_NEAR(b2.x, b.x, 1e-9);
    EXPECT_NEAR(b2.y, b.y, 1e-9);
    EXPECT_NEAR(wrap_angle(b2.theta - b.theta), 0.0, 1e-12);
    const Pose2 d{pos(rng), pos(rng), ang(rng)};
    const Pose2 d2 = between(a, compose(a, d));
    EXPECT_NEAR(d2.x, d.x, 1e-9);
    EXPECT_NEAR(d2.y, d.y, 1e-9);
    EXPECT_NEAR(wrap_angle(d2.theta - d.theta), 0.0, 1e-12);
  }
}

TEST(Pose2, BetweenItselfIsIdentity) {
  const Pose2 a{-3, 7, 2.5};
  const Pose2 d = between(a, a);
  EXPECT_NEAR(d.x, 0, 1e-15);
  EXPECT_NEAR(d.y, 0, 1e-15);
  EXPECT_NEAR(d.theta, 0, 1e-15);
}

}  // namespace
}  // namespace seqtopo::trajectory
