#pragma once
// A synthetic test world: a 10 m square driven twice in 0.5 m steps, with odometry that drifts (scale
// and heading bias) and jitters. The second lap revisits every place of the first.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "seqtopo/core/pose2.hpp"

namespace seqtopo::trajectory::test_support {

// Two trajectories equal pose by pose within tol [m, rad].
inline void expect_same_poses(const std::vector<Pose2>& a, const std::vector<Pose2>& b, double tol) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(a[i].x, b[i].x, tol) << "pose " << i;
    EXPECT_NEAR(a[i].y, b[i].y, tol) << "pose " << i;
    EXPECT_NEAR(wrap_angle(a[i].theta - b[i].theta), 0.0, tol) << "pose " << i;
  }
}

struct SquareLoop {
  std::vector<Pose2> truth;
  std::vector<Pose2> odometry;
  std::vector<int> labels;                                 // place = position along the lap
  std::vector<std::pair<std::size_t, std::size_t>> pairs;  // (second-lap image, first-lap image)
};

// Standard normal from a fixed-algorithm engine (std::normal_distribution differs between libraries).
class Gaussian {
 public:
  explicit Gaussian(std::uint32_t seed) : rng_(seed) {}
  double operator()() {
    const double u1 = (static_cast<double>(rng_()) + 0.5) / 4294967296.0;
    const double u2 = (static_cast<double>(rng_()) + 0.5) / 4294967296.0;
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }

 private:
  std::mt19937 rng_;
};

inline SquareLoop square_loop(std::uint32_t seed = 7, double heading_bias = 0.006 /* [rad/step] */) {
  constexpr int steps_per_side = 20;
  constexpr double step = 0.5;  // [m]
  constexpr int per_lap = 4 * steps_per_side;
  constexpr int images = 2 * per_lap + 1;
  SquareLoop w;
  for (int k = 0; k < images; ++k) {
    const int along = k % per_lap;
    const int side = along / steps_per_side;
    const double t = step * (along % steps_per_side);
    const double corner_x[] = {0, 10, 10, 0}, corner_y[] = {0, 0, 10, 10};
    const double dir_x[] = {1, 0, -1, 0}, dir_y[] = {0, 1, 0, -1};
    w.truth.push_back(
        {corner_x[side] + t * dir_x[side], corner_y[side] + t * dir_y[side], wrap_angle(side * std::numbers::pi / 2)});
    w.labels.push_back(along);
    if (k >= per_lap) w.pairs.emplace_back(static_cast<std::size_t>(k), static_cast<std::size_t>(k - per_lap));
  }
  Gaussian noise(seed);
  w.odometry.push_back(w.truth[0]);
  for (int k = 1; k < images; ++k) {
    const Pose2 u = between(w.truth[k - 1], w.truth[k]);
    const Pose2 measured{u.x * 1.03 + 0.01 * noise(), u.y + 0.01 * noise(), u.theta + heading_bias + 0.003 * noise()};
    w.odometry.push_back(compose(w.odometry.back(), measured));
  }
  return w;
}

}  // namespace seqtopo::trajectory::test_support
