#pragma once
// A planar pose and the two operations odometry needs: vocabulary shared by the readers, the mapping,
// the trajectory estimators and the plots, so it sits at the bottom of the tree.
#include <cmath>
#include <numbers>

namespace seqtopo {

// T_world_robot: the robot's position [m, m] and heading [rad] in the world frame.
struct Pose2 {
  double x = 0, y = 0, theta = 0;
  friend bool operator==(const Pose2&, const Pose2&) = default;
};

// Angle in [-pi, pi) [rad].
inline double wrap_angle(double a) {
  constexpr double two_pi = 2.0 * std::numbers::pi;
  if (a >= -std::numbers::pi && a < std::numbers::pi) return a;  // exact when nothing to do
  a = std::fmod(a + std::numbers::pi, two_pi);
  if (a < 0) a += two_pi;
  return a - std::numbers::pi;
}

// Motion from a to b expressed in a's frame (T_a_b = T_world_a^-1 * T_world_b): what a wheel odometer
// reports between the two poses.
inline Pose2 between(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  const double dx = b.x - a.x, dy = b.y - a.y;
  return {c * dx + s * dy, -s * dx + c * dy, wrap_angle(b.theta - a.theta)};
}

// Applies a motion expressed in a's frame (T_world_a * T_a_b); compose(a, between(a, b)) == b.
inline Pose2 compose(const Pose2& a, const Pose2& delta) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  return {a.x + c * delta.x - s * delta.y, a.y + s * delta.x + c * delta.y, wrap_angle(a.theta + delta.theta)};
}

}  // namespace seqtopo
