#pragma once
// 2-D points and poses of the simulated floor plan. World frame: x east, y north [m]; angles
// counter-clockwise from +x [rad].
#include <cmath>

#include "seqtopo/core/pose2.hpp"

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

// Poses and angle wrapping are the tree's own (core/pose2.hpp).
using seqtopo::Pose2;
using seqtopo::wrap_angle;

// Axis-aligned rectangle [x0, x1] x [y0, y1] [m].
struct Rect {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
};

}  // namespace seqtopo::simulator
