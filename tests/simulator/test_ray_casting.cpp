// Ray casting and rendering against analytic cases: a square room whose four walls have four colours.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "seqtopo/simulator/random.hpp"
#include "seqtopo/simulator/render.hpp"
#include "seqtopo/simulator/world.hpp"

namespace seqtopo::simulator {
namespace {

constexpr double kPi = std::numbers::pi;

// Free space [1, 9] x [1, 9] inside solid walls; east wall red, north green, west blue, south yellow.
GridWorld box_room() {
  GridWorld w({0, 0, 10, 10}, 0.25);
  w.add_ground({Pattern::stripes, rgb(128, 128, 128), rgb(128, 128, 128), 1.0, true});
  auto uniform = [&](Colour c) { return w.add_material({Pattern::stripes, c, c, 2.6, 1.0}); };
  w.fill({0, 0, 10, 10}, uniform(rgb(220, 200, 40)));
  w.fill({9, 0, 10, 10}, uniform(rgb(220, 30, 30)));
  w.fill({0, 9, 10, 10}, uniform(rgb(30, 220, 30)));
  w.fill({0, 0, 1, 10}, uniform(rgb(30, 30, 220)));
  w.carve({1, 1, 9, 9}, 0);
  return w;
}

// Distance from p along angle a to the boundary of [1, 9]^2, computed directly.
double analytic_distance(Vec2 p, double a) {
  const double c = std::cos(a), s = std::sin(a);
  double best = 1e18;
  if (c > 1e-12) best = std::min(best, (9 - p.x) / c);
  if (c < -1e-12) best = std::min(best, (1 - p.x) / c);
  if (s > 1e-12) best = std::min(best, (9 - p.y) / s);
  if (s < -1e-12) best = std::min(best, (1 - p.y) / s);
  return best;
}

TEST(RayCasting, DistancesAtKnownAngles) {
  const GridWorld w = box_room();
  struct Case {
    Vec2 from;
    double angle, distance;
    Side side;
  };
  const Case cases[] = {
      {{5, 5}, 0.0, 4.0, Side::west},  // east wall, seen face is the wall cell's west side
      {{5, 5}, kPi / 2, 4.0, Side::south},
      {{5, 5}, kPi, 4.0, Side::east},
      {{5, 5}, -kPi / 2, 4.0, Side::north},
      {{5, 5}, kPi / 6, 4.0 / std::cos(kPi / 6), Side::west},   // 30 degrees: x = 9 at y = 7.31
      {{5, 5}, kPi / 3, 4.0 / std::sin(kPi / 3), Side::south},  // 60 degrees: y = 9 at x = 7.31
      {{3, 5}, kPi / 4, 4.0 * std::sqrt(2.0), Side::south},     // 45 degrees: y = 9 at x = 7
      {{2.1, 1.6}, kPi, 1.1, Side::east},
  };
  for (const Case& c : cases) {
    const RayHit hit = w.cast(c.from, c.angle);
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.distance, c.distance, 1e-9) << "angle " << c.angle;
    EXPECT_EQ(hit.side, c.side) << "angle " << c.angle;
    EXPECT_NEAR(hit.point.x, c.from.x + c.distance * std::cos(c.angle), 1e-9);
    EXPECT_NEAR(hit.point.y, c.from.y + c.distance * std::sin(c.angle), 1e-9);
  }
}

TEST(RayCasting, RandomRaysMatchTheAnalyticDistance) {
  const GridWorld w = box_room();
  Rng rng(42);
  for (int k = 0; k < 2000; ++k) {
    const Vec2 p{rng.uniform(1.05, 8.95), rng.uniform(1.05, 8.95)};
    const double a = rng.uniform(-kPi, kPi);
    const RayHit hit = w.cast(p, a);
    ASSERT_TRUE(hit.hit);
    ASSERT_NEAR(hit.distance, analytic_distance(p, a), 1e-9) << p.x << "," << p.y << " angle " << a;
  }
}

TEST(RayCasting, MaxDistanceAndOutsideMiss) {
  const GridWorld w = box_room();
  EXPECT_FALSE(w.cast({5, 5}, 0.0, 3.9).hit);
  EXPECT_TRUE(w.cast({5, 5}, 0.0, 4.1).hit);
  EXPECT_FALSE(w.cast({-5, 5}, 0.0).hit);
}

Lighting no_noise() {
  Lighting l;
  l.noise_sigma = 0;
  return l;
}

bool dominant(const RgbImage& im, int x, int y, int channel) {
  const std::uint8_t* p = im.at(x, y);
  for (int c = 0; c < 3; ++c) {
    if (c != channel && p[c] + 40 > p[channel]) return false;
  }
  return true;
}

TEST(Panorama, ColumnZeroIsTheHeadingAndAnglesIncreaseCounterClockwise) {
  const GridWorld w = box_room();
  PanoramaCamera cam;
  cam.supersample = 1;
  const int mid = cam.height / 2;
  const RgbImage east = render_panorama(w, {5, 5, 0.0}, cam, no_noise());
  EXPECT_TRUE(dominant(east, 0, mid, 0));              // heading: the red east wall
  EXPECT_TRUE(dominant(east, cam.width / 4, mid, 1));  // 90 degrees left: green north wall
  EXPECT_TRUE(dominant(east, cam.width / 2, mid, 2));  // behind: blue west wall
  const std::uint8_t* south = east.at(3 * cam.width / 4, mid);
  EXPECT_GT(south[0], 120);  // 90 degrees right: yellow
  EXPECT_GT(south[1], 120);
  EXPECT_LT(south[2], 80);
  const RgbImage north = render_panorama(w, {5, 5, kPi / 2}, cam, no_noise());
  EXPECT_TRUE(dominant(north, 0, mid, 1));
  EXPECT_TRUE(dominant(north, cam.width / 4, mid, 2));
}

TEST(Panorama, WallSpansTheElevationsOfItsFloorAndTop) {
  // From the centre the walls are 4 m away: camera 1.5 m up, ceiling 2.6 m. The wall foot is at
  // -atan(1.5 / 4) = -20.56 degrees and its top at atan(1.1 / 4) = 15.38 degrees; with one row per
  // degree from +30 (row 0) to -30 those are rows 50.06 and 14.12.
  const GridWorld w = box_room();
  PanoramaCamera cam;
  cam.supersample = 1;
  const RgbImage im = render_panorama(w, {5, 5, 0.0}, cam, no_noise());
  for (int row = 16; row <= 48; ++row) EXPECT_TRUE(dominant(im, 0, row, 0)) << "row " << row;
  for (int row = 52; row < 60; ++row) EXPECT_FALSE(dominant(im, 0, row, 0)) << "floor row " << row;
  for (int row = 0; row <= 12; ++row) EXPECT_FALSE(dominant(im, 0, row, 0)) << "ceiling row " << row;
  // Nearer the east wall (2 m), the wall covers more rows: the foot at -36.9 degrees is below the image.
  const RgbImage near = render_panorama(w, {7, 5, 0.0}, cam, no_noise());
  for (int row = 30; row < 60; ++row) EXPECT_TRUE(dominant(near, 0, row, 0)) << "row " << row;
}

TEST(Pinhole, CentreLooksAheadAndEdgesSeeTheSideWalls) {
  const GridWorld w = box_room();
  PinholeCamera cam;
  cam.supersample = 1;
  // Heading north-east from near the south-west corner: the centre sees a corner between the north and
  // east walls; turned to heading 0 the whole centre column is the red east wall.
  const RgbImage ahead = render_pinhole(w, {5, 5, 0.0}, cam, no_noise());
  EXPECT_TRUE(dominant(ahead, cam.width / 2, cam.height / 2, 0));
  // Close to the north wall, looking east: the left edge sees the green north wall.
  const RgbImage left = render_pinhole(w, {4, 8.5, 0.0}, cam, no_noise());
  EXPECT_TRUE(dominant(left, 2, cam.height / 2, 1));
  EXPECT_TRUE(dominant(left, cam.width / 2, cam.height / 2, 0));
}

TEST(Rendering, NoiseIsSeededAndBounded) {
  const GridWorld w = box_room();
  PanoramaCamera cam;
  cam.width = 72;
  cam.height = 12;
  Lighting noisy;
  noisy.noise_sigma = 3;
  const RgbImage a = render_panorama(w, {5, 5, 0.3}, cam, noisy, 7);
  const RgbImage b = render_panorama(w, {5, 5, 0.3}, cam, noisy, 7);
  const RgbImage c = render_panorama(w, {5, 5, 0.3}, cam, noisy, 8);
  const RgbImage clean = render_panorama(w, {5, 5, 0.3}, cam, no_noise(), 7);
  EXPECT_EQ(a.pixels, b.pixels);
  EXPECT_NE(a.pixels, c.pixels);
  double sum2 = 0;
  for (std::size_t k = 0; k < a.pixels.size(); ++k) {
    const double d = static_cast<double>(a.pixels[k]) - clean.pixels[k];
    sum2 += d * d;
    EXPECT_LE(std::abs(d), 3 * 3.5 + 1);  // the approximate Gaussian is bounded at 3.46 sigma
  }
  const double sigma = std::sqrt(sum2 / static_cast<double>(a.pixels.size()));
  EXPECT_GT(sigma, 2.0);
  EXPECT_LT(sigma, 4.0);
}

TEST(World, DecalsPaintOnlyTheirFaces) {
  GridWorld w = box_room();
  Decal d;
  d.side = Side::west;  // on the east wall, facing the room
  d.plane = 9.0;
  d.u0 = 4.0;
  d.u1 = 6.0;
  d.z0 = 1.0;
  d.z1 = 2.0;
  d.fill = rgb(10, 10, 10);
  w.add_decal(d);
  const int cx = w.cell_x(9.1), cy = w.cell_y(5.0);
  EXPECT_EQ(w.wall_colour(cx, cy, Side::west, 5.0, 1.5), rgb(10, 10, 10));
  EXPECT_NE(w.wall_colour(cx, cy, Side::west, 5.0, 2.2), rgb(10, 10, 10));
  EXPECT_NE(w.wall_colour(cx, w.cell_y(3.0), Side::west, 3.0, 1.5), rgb(10, 10, 10));
  EXPECT_THROW(w.add_decal(Decal{}), std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::simulator
