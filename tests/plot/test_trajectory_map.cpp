#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "seqtopo/plot/png.hpp"
#include "seqtopo/plot/trajectory_map.hpp"

namespace seqtopo::plot {
namespace {

// A 10 m square driven twice: the second lap revisits the first (true pose, and a drifting copy).
struct Loop {
  std::vector<Pose2> truth, drifted;
  std::vector<int> labels;
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
};

Loop square_loop() {
  Loop l;
  Pose2 odo;
  for (int k = 0; k <= 80; ++k) {
    const int along = k % 40;
    const int side = along / 10;
    const double t = along % 10;
    const double cx[] = {0, 10, 10, 0}, cy[] = {0, 0, 10, 10}, dx[] = {1, 0, -1, 0}, dy[] = {0, 1, 0, -1};
    l.truth.push_back({cx[side] + t * dx[side], cy[side] + t * dy[side], side * std::numbers::pi / 2});
    if (k > 0) odo = compose(odo, between(l.truth[k - 1], l.truth[k]));
    odo.theta += 0.01;  // heading drift [rad/step]
    l.drifted.push_back(odo);
    // Places 0..9 (the first side) are revisited; the rest get labels of their own.
    l.labels.push_back(along < 10 ? along : 1000 + k);
    if (k >= 40 && along < 10) l.pairs.emplace_back(k, k - 40);
  }
  return l;
}

bool is_background(const RgbImage& img, int x, int y) {
  const auto* p = img.at(x, y);
  return p[0] == 255 && p[1] == 255 && p[2] == 255;
}

int non_background(const RgbImage& img, int x0, int x1, int y0, int y1) {
  int n = 0;
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) n += is_background(img, x, y) ? 0 : 1;
  }
  return n;
}

int pixels_of_colour(const RgbImage& img, int x0, int x1, const std::array<std::uint8_t, 3>& rgb) {
  int n = 0;
  for (int y = 0; y < img.height; ++y) {
    for (int x = x0; x < x1; ++x) {
      const auto* p = img.at(x, y);
      n += (p[0] == rgb[0] && p[1] == rgb[1] && p[2] == rgb[2]) ? 1 : 0;
    }
  }
  return n;
}

TEST(MetricMap, PanelsSideBySideEachWithContent) {
  const Loop l = square_loop();
  const std::vector<TrajectoryPanel> panels{
      {"(a) Cumulative odometry", l.drifted}, {"(b) Pose graph", l.truth}, {"(c) Ground truth", l.truth}};
  TrajectoryMapConfig config;
  const RgbImage img = trajectory_map_image(panels, l.labels, l.pairs, config);
  EXPECT_EQ(img.width, 3 * config.panel_width);
  EXPECT_EQ(img.height, config.panel_height);
  ASSERT_EQ(img.pixels.size(), static_cast<std::size_t>(img.width) * img.height * 3);
  for (int k = 0; k < 3; ++k) {
    const int x0 = k * config.panel_width;
    // Something is drawn in the middle of every panel (the data), not only on its axes.
    const int inner = non_background(img, x0 + 150, x0 + config.panel_width - 100, 120, config.panel_height - 150);
    EXPECT_GT(inner, 500) << "panel " << k;
    // Revisited places show in their own colour, single visits in grey.
    EXPECT_GT(pixels_of_colour(img, x0, x0 + config.panel_width, place_colour(3)), 5) << "panel " << k;
    EXPECT_GT(pixels_of_colour(img, x0, x0 + config.panel_width, kSingleVisitColour), 20) << "panel " << k;
  }
  EXPECT_FALSE(encode_png(img).empty());
}

TEST(MetricMap, WithoutLabelsOrPairs) {
  const Loop l = square_loop();
  TrajectoryMapConfig config;
  config.panel_width = 300;
  config.panel_height = 250;
  const RgbImage img = trajectory_map_image({{"odometry", l.drifted}}, {}, {}, config);
  EXPECT_EQ(img.width, 300);
  EXPECT_EQ(img.height, 250);
  EXPECT_GT(non_background(img, 80, 280, 45, 190), 100);
  // A single pose and an empty panel still draw their axes.
  const RgbImage one = trajectory_map_image({{"one", {{1, 2, 0}}}, {"none", {}}}, {}, {});
  EXPECT_EQ(one.width, 2 * TrajectoryMapConfig{}.panel_width);
  EXPECT_GT(non_background(one, 640, 1280, 0, 640), 100);
}

TEST(MetricMap, PlaceColoursDiffer) {
  for (int a = 0; a < 20; ++a) {
    for (int b = a + 1; b < 20; ++b) EXPECT_NE(place_colour(a), place_colour(b)) << a << " " << b;
  }
}

TEST(MetricMap, Misuse) {
  const Loop l = square_loop();
  EXPECT_THROW(trajectory_map_image({}, {}, {}), std::invalid_argument);
  EXPECT_THROW(trajectory_map_image({{"a", l.truth}}, {1, 2}, {}), std::invalid_argument);
  EXPECT_THROW(trajectory_map_image({{"a", l.truth}}, {}, {{0, l.truth.size()}}), std::invalid_argument);
  EXPECT_THROW(trajectory_map_image({{"a", {{NAN, 0, 0}}}}, {}, {}), std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::plot
