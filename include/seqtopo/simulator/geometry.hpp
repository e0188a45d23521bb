#pragma once
// 2-D points and poses of the simulated floor plan. World frame: x east, y north [m]; angles
// counter-clockwise from +x [rad].
#include <cmath>
#include <numbers>

namespace seqtopo::simulator {

struct Vec2 {
  double x = 0.0;
  double y = 0.0;
  friend Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
  friend Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
  friend Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
  friend bool operator==(Vec2, Vec2) = default;
};

inline double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
inline double norm(Vec2 a) { return std::hypot(a.x, a.y); }
inline double distance(Vec2 a, Vec2 b) { return norm(a - b); }

// T_world_robot in 2-D: position [m] and heading [rad].
struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;
  friend bool operator==(const Pose2&, const Pose2&) = default;
};

// Angle wrapped to (-pi, pi].
inline double wrap_angle(double a) {
  a = std::remainder(a, 2.0 * std::numbers::pi);
  return a <= -std::numbers::pi ? a + 2.0 * std::numbers::pi : a;
}

// Axis-aligned rectangle [x0, x1] x [y0, y1] [m].
struct Rect {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
};

}  // namespace seqtopo::simulator
