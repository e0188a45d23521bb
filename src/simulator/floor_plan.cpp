// Top view of a scenario (floor_plan.png).
#include <algorithm>
#include <cmath>
#include <set>

#include "seqtopo/simulator/scenarios.hpp"

namespace seqtopo::simulator {
namespace {

using Pixel = std::array<std::uint8_t, 3>;

struct Canvas {
  RgbImage image;
  Rect bounds;
  double ppm = 1;
  std::pair<double, double> to_px(Vec2 p) const { return {(p.x - bounds.x0) * ppm, (bounds.y1 - p.y) * ppm}; }
  void dot(int x, int y, Pixel c) {
    if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
    std::copy(c.begin(), c.end(), image.at(x, y));
  }
  void disc(double x, double y, double r, Pixel c) {
    for (int dy = static_cast<int>(-std::ceil(r)); dy <= std::ceil(r); ++dy) {
      for (int dx = static_cast<int>(-std::ceil(r)); dx <= std::ceil(r); ++dx) {
        if (dx * dx + dy * dy <= r * r)
          dot(static_cast<int>(std::lround(x)) + dx, static_cast<int>(std::lround(y)) + dy, c);
      }
    }
  }
  void ring(double x, double y, double r, Pixel c) {
    for (int k = 0; k < 64; ++k) {
      const double a = 2 * std::numbers::pi * k / 64;
      disc(x + r * std::cos(a), y + r * std::sin(a), 1.0, c);
    }
  }
  void line(Vec2 a, Vec2 b, double radius, Pixel c) {
    const auto [ax, ay] = to_px(a);
    const auto [bx, by] = to_px(b);
    const int steps = std::max(1, static_cast<int>(std::ceil(std::max(std::abs(bx - ax), std::abs(by - ay)))));
    for (int k = 0; k <= steps; ++k) {
      const double t = static_cast<double>(k) / steps;
      disc(ax + t * (bx - ax), ay + t * (by - ay), radius, c);
    }
  }
};

Pixel pixel(Colour c, float scale = 1.0F, float towards_white = 0.0F) {
  Pixel p{};
  for (int k = 0; k < 3; ++k) {
    const float v = c[static_cast<std::size_t>(k)] * scale;
    p[static_cast<std::size_t>(k)] =
        static_cast<std::uint8_t>(std::clamp(v + (255.0F - v) * towards_white, 0.0F, 255.0F));
  }
  return p;
}

}  // namespace

RgbImage draw_floor_plan(const ScenarioSetup& setup, const SimulatedRun& run, double pixels_per_metre) {
  const GridWorld& w = setup.world;
  Canvas canvas;
  canvas.bounds = w.bounds();
  const double span = std::max(canvas.bounds.x1 - canvas.bounds.x0, canvas.bounds.y1 - canvas.bounds.y0);
  canvas.ppm = std::min(pixels_per_metre, 2400.0 / span);
  canvas.image = RgbImage(static_cast<int>(std::ceil((canvas.bounds.x1 - canvas.bounds.x0) * canvas.ppm)),
                          static_cast<int>(std::ceil((canvas.bounds.y1 - canvas.bounds.y0) * canvas.ppm)));
  for (int py = 0; py < canvas.image.height; ++py) {
    for (int px = 0; px < canvas.image.width; ++px) {
      const Vec2 p{canvas.bounds.x0 + (px + 0.5) / canvas.ppm, canvas.bounds.y1 - (py + 0.5) / canvas.ppm};
      const int cx = w.cell_x(p.x), cy = w.cell_y(p.y);
      if (!w.inside(cx, cy)) continue;
      Pixel c{};
      if (w.solid(cx, cy)) {
        const Material& m = w.material(w.material_at(cx, cy));
        c = m.height < 2.0 ? pixel(m.base, 0.8F) : pixel(m.base, 0.5F);
      } else {
        const Ground& g = w.ground(w.ground_at(cx, cy));
        c = pixel(g.base, 1.0F, g.roofed ? 0.55F : 0.3F);
      }
      canvas.dot(px, py, c);
    }
  }
  // Decals as coloured strokes on the free side of their wall.
  for (const Decal& d : w.decals()) {
    const double out = 0.12;  // [m] into the free space
    Vec2 a, b;
    switch (d.side) {
      case Side::west:
        a = {d.plane - out, d.u0};
        b = {d.plane - out, d.u1};
        break;
      case Side::east:
        a = {d.plane + out, d.u0};
        b = {d.plane + out, d.u1};
        break;
      case Side::south:
        a = {d.u0, d.plane - out};
        b = {d.u1, d.plane - out};
        break;
      case Side::north:
        a = {d.u0, d.plane + out};
        b = {d.u1, d.plane + out};
        break;
    }
    canvas.line(a, b, std::max(1.0, 0.08 * canvas.ppm), pixel(d.fill));
  }
  // The route: the path followed (grey) and the robot's actual trajectory (red).
  for (std::size_t k = 1; k < run.on_path.size(); ++k)
    canvas.line(run.on_path[k - 1], run.on_path[k], 1.0, {90, 90, 90});
  for (std::size_t k = 1; k < run.poses.size(); ++k) {
    canvas.line({run.poses[k - 1].x, run.poses[k - 1].y}, {run.poses[k].x, run.poses[k].y}, 1.2, {220, 20, 20});
  }
  // Junctions of the route.
  std::set<int> used;
  for (const RouteLeg& leg : setup.legs) {
    for (std::size_t k = 0; k + 1 < leg.nodes.size(); ++k)
      used.insert(setup.graph.edge_between(leg.nodes[k], leg.nodes[k + 1]));
  }
  std::vector<int> degree(setup.graph.nodes.size(), 0);
  for (int e : used) {
    for (int v : setup.graph.edges[static_cast<std::size_t>(e)]) ++degree[static_cast<std::size_t>(v)];
  }
  for (std::size_t v = 0; v < degree.size(); ++v) {
    if (degree[v] < 3) continue;
    const auto [x, y] = canvas.to_px(setup.graph.nodes[v]);
    canvas.ring(x, y, 1.2 * canvas.ppm, {0, 0, 0});
  }
  if (!run.poses.empty()) {
    const auto [sx, sy] = canvas.to_px({run.poses.front().x, run.poses.front().y});
    canvas.disc(sx, sy, 5, {20, 170, 40});
    const auto [ex, ey] = canvas.to_px({run.poses.back().x, run.poses.back().y});
    canvas.disc(ex, ey, 5, {30, 60, 220});
  }
  // Survey points and their adjacency.
  for (const auto& [t, m] : run.adjacency) {
    const Pose2& a = run.points[static_cast<std::size_t>(t)].pose;
    const Pose2& b = run.points[static_cast<std::size_t>(m)].pose;
    canvas.line({a.x, a.y}, {b.x, b.y}, 0.6, {120, 120, 120});
  }
  for (const SurveyPoint& p : run.points) {
    const auto [x, y] = canvas.to_px({p.pose.x, p.pose.y});
    if (p.map) {
      canvas.disc(x, y, std::max(3.0, 0.2 * canvas.ppm), {30, 60, 220});
    } else {
      canvas.disc(x, y, std::max(2.5, 0.14 * canvas.ppm), {240, 130, 20});
    }
  }
  return canvas.image;
}

}  // namespace seqtopo::simulator
