// The static figures have what a paper needs, checked on their pixels: the matrix figure's axes (tick marks in
// the margins at the tick positions), its colour bar (a gradient from white to black) and its legend; the PR
// curve's precision label beside its axis (not on the 1.0 tick), a curve at precision 1.0 inside the frame and
// the first method drawn on top; the metric map's legend. The display range of a large matrix from a sample.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <set>

#include "seqtopo/plot/matrix_image.hpp"
#include "seqtopo/plot/pr_curve.hpp"
#include "seqtopo/plot/trajectory_map.hpp"

namespace seqtopo::plot {
namespace {

bool dark(const RgbImage& img, int x, int y) {
  const auto* p = img.at(x, y);
  return p[0] < 80 && p[1] < 80 && p[2] < 80;
}

bool is(const RgbImage& img, int x, int y, std::array<std::uint8_t, 3> rgb, int tolerance = 30) {
  const auto* p = img.at(x, y);
  return std::abs(p[0] - rgb[0]) <= tolerance && std::abs(p[1] - rgb[1]) <= tolerance &&
         std::abs(p[2] - rgb[2]) <= tolerance;
}

int count(const RgbImage& img, int x0, int x1, int y0, int y1, const std::function<bool(int, int)>& f) {
  int n = 0;
  for (int y = std::max(0, y0); y < std::min(img.height, y1); ++y) {
    for (int x = std::max(0, x0); x < std::min(img.width, x1); ++x) n += f(x, y) ? 1 : 0;
  }
  return n;
}

// A 100 x 100 matrix of a ramp, drawn 512 px a side (scale 6 -> 600 px): the frame, ticks and bar are findable.
DenseMatrix<float> ramp() {
  DenseMatrix<float> m(100, 100, 0.0F);
  for (std::size_t i = 0; i < 100; ++i) {
    for (std::size_t j = 0; j < 100; ++j) m(i, j) = static_cast<float>(i + j);
  }
  return m;
}

TEST(MatrixFigure, HasIndexTicksAColourBarAndALegend) {
  MatrixFigureConfig config;
  config.legend = {{"kept", {255, 30, 30}, LegendEntry::Mark::line},
                   {"pruned", {40, 110, 255}, LegendEntry::Mark::line}};
  config.title = "ramp";
  const RgbImage img = matrix_figure(ramp(), {}, config);
  const RgbImage core = matrix_image(ramp());
  ASSERT_EQ(core.width, 600);
  // The figure is the matrix plus margins on every side.
  EXPECT_GT(img.width, core.width + 150);
  EXPECT_GT(img.height, core.height + 60);
  // Find the matrix: the block of pixels equal to the core image.
  int left = -1, top = -1;
  for (int y = 0; y < img.height - core.height && left < 0; ++y) {
    for (int x = 0; x < img.width - core.width; ++x) {
      bool same = true;
      for (int row : {100, 300, 500}) {
        same = same && std::equal(core.at(0, row), core.at(0, row) + 3 * core.width, img.at(x, y + row));
      }
      if (same) {
        left = x, top = y;
        break;
      }
    }
  }
  ASSERT_GE(left, 0) << "the matrix is not drawn as matrix_image draws it";
  const int bottom = top + core.height, right = left + core.width;
  // Tick marks below the matrix at indices 0, 20, ..., 100 (6 px per index), and nothing dark between them.
  for (int v = 0; v <= 100; v += 20) {
    const int x = left + v * 6;
    EXPECT_GE(count(img, x - 1, x + 2, bottom + 2, bottom + 8, [&](int a, int b) { return dark(img, a, b); }), 4)
        << "no tick mark at column index " << v;
    EXPECT_GE(count(img, left - 12, left - 1, top + v * 6 - 1, top + v * 6 + 2,
                    [&](int a, int b) { return dark(img, a, b); }),
              4)
        << "no tick mark at row index " << v;
  }
  EXPECT_EQ(count(img, left + 60, left + 61, bottom + 2, bottom + 8, [&](int a, int b) { return dark(img, a, b); }), 0);
  // Tick labels below the ticks and left of them: dark text pixels in the margins.
  EXPECT_GT(count(img, left - 10, right + 10, bottom + 9, bottom + 25, [&](int a, int b) { return dark(img, a, b); }),
            40);
  EXPECT_GT(count(img, 0, left - 12, top, bottom, [&](int a, int b) { return dark(img, a, b); }), 60);
  // The colour bar right of the matrix: a column whose grey level falls from white at the top to black at the
  // bottom, through at least 100 levels.
  int bar_x = -1;
  for (int x = right + 5; x < img.width && bar_x < 0; ++x) {
    const auto* top_pixel = img.at(x, top + core.height / 2 - 150);
    const auto* low_pixel = img.at(x, top + core.height / 2 + 150);
    if (top_pixel[0] > 200 && low_pixel[0] < 60 && top_pixel[0] == top_pixel[1] && low_pixel[1] == low_pixel[2])
      bar_x = x;
  }
  ASSERT_GE(bar_x, 0) << "no colour bar right of the matrix";
  std::set<int> levels;
  int previous = 256, rises = 0;
  for (int y = top; y < bottom; ++y) {
    const auto* p = img.at(bar_x + 3, y);
    if (p[0] != p[1] || p[1] != p[2]) continue;
    if (p[0] == 0 && levels.empty()) continue;  // the bar's frame
    levels.insert(p[0]);
    rises += p[0] > previous + 2 ? 1 : 0;
    previous = p[0];
  }
  EXPECT_GE(levels.size(), 100U);
  EXPECT_LE(rises, 2) << "the colour bar is not a gradient from white (top) to black (bottom)";
  // Value ticks beside the bar.
  EXPECT_GT(count(img, bar_x + 16, bar_x + 60, top, bottom, [&](int a, int b) { return dark(img, a, b); }), 40);
  // The legend below: both entries' colours.
  EXPECT_GT(count(img, 0, img.width, bottom + 30, img.height,
                  [&](int a, int b) {
                    return is(img, a, b, {255, 30, 30});
                  }),
            20);
  EXPECT_GT(count(img, 0, img.width, bottom + 30, img.height,
                  [&](int a, int b) {
                    return is(img, a, b, {40, 110, 255});
                  }),
            20);
}

// The exact percentiles (a full sort) of the finite values.
ValueRange sorted_percentiles(const DenseMatrix<float>& m) {
  std::vector<float> v;
  for (float x : m.values) {
    if (std::isfinite(x)) v.push_back(x);
  }
  std::sort(v.begin(), v.end());
  return {v[v.size() / 100], v[v.size() - 1 - v.size() / 100]};
}

// Up to kDisplayRangeSample values the display range is exact; above, the percentiles of a strided sample that
// sees every column, near the exact ones.
TEST(DisplayRange, ExactWhenSmallSampledWhenLarge) {
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(0.0F, 1.0F);
  DenseMatrix<float> small(1000, 1000);  // 10^6 values <= 2^20: every value
  for (auto& v : small.values) v = noise(rng);
  small(3, 4) = std::numeric_limits<float>::quiet_NaN();
  const ValueRange exact = sorted_percentiles(small), got = display_range(small);
  EXPECT_EQ(got.lo, exact.lo);
  EXPECT_EQ(got.hi, exact.hi);

  DenseMatrix<float> large(3600, 3600);
  for (auto& v : large.values) v = noise(rng);
  const ValueRange reference = sorted_percentiles(large), sampled = display_range(large);
  EXPECT_NEAR(sampled.lo, reference.lo, 0.02);  // the 1st percentile of N(0, 1) is -2.33
  EXPECT_NEAR(sampled.hi, reference.hi, 0.02);
  const ValueRange again = display_range(large);
  EXPECT_EQ(again.lo, sampled.lo);
  EXPECT_EQ(again.hi, sampled.hi);

  // 1100 x 1100 values give stride 2, which would see only the even columns: the stride is raised to one coprime
  // to the row length, and the odd columns' value is seen.
  DenseMatrix<float> stripes(1100, 1100);
  for (std::size_t i = 0; i < stripes.rows; ++i) {
    for (std::size_t j = 0; j < stripes.cols; ++j) stripes(i, j) = static_cast<float>(j % 2);
  }
  const ValueRange r = display_range(stripes);
  EXPECT_EQ(r.lo, 0.0F);
  EXPECT_EQ(r.hi, 1.0F);
  // min..max (not robust) looks at every value
  large(1234, 2345) = 40.0F;
  EXPECT_EQ(display_range(large, false).hi, 40.0F);
}

TEST(PrCurve, PrecisionOneInsideTheFrameAndTheMethodOnTop) {
  const int w = 560, h = 440;
  Curve method{"method", {{0.1, 1.0}, {0.5, 1.0}, {0.9, 1.0}}, {220, 30, 30}};
  Curve baseline{"baseline", {{0.1, 1.0}, {0.5, 1.0}, {0.9, 1.0}}, {40, 90, 220}};
  const RgbImage img = pr_curve_image({method, baseline}, w, h);
  const auto [x1, y1] = pr_curve_pixel(0.5, 1.0, w, h);
  const auto [x0, y0] = pr_curve_pixel(0.0, 0.0, w, h);
  // The frame's top is above precision 1.0 by at least 10 pixels, and the curve is there.
  int frame_top = -1;
  for (int y = 0; y < y1 && frame_top < 0; ++y) {
    if (dark(img, x1, y)) frame_top = y;
  }
  ASSERT_GE(frame_top, 0);
  EXPECT_GE(y1 - frame_top, 10);
  // Where both curves coincide the method (the first curve) shows, not the baseline drawn under it.
  EXPECT_TRUE(is(img, x1, y1, method.rgb)) << "the first curve is hidden under the second";
  EXPECT_EQ(count(img, x1 - 20, x1 + 20, y1 - 1, y1 + 2, [&](int a, int b) { return is(img, a, b, baseline.rgb); }), 0);
  // "precision" is written upwards beside the axis: its pixels (left of the tick labels) span more height than
  // width, and none of them is on the row of the 1.0 tick label.
  int min_y = h, max_y = 0, min_x = w, max_x = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < 28; ++x) {
      if (!dark(img, x, y)) continue;
      min_y = std::min(min_y, y), max_y = std::max(max_y, y), min_x = std::min(min_x, x), max_x = std::max(max_x, x);
    }
  }
  ASSERT_LT(min_y, max_y) << "no axis label left of the tick labels";
  EXPECT_GT(max_y - min_y, 3 * (max_x - min_x));
  EXPECT_GT(min_y, y1 + 10) << "the precision label is on the 1.0 tick";
  EXPECT_LT(max_y, y0);
  // Both curves are in the legend.
  EXPECT_GT(count(img, x0, x0 + 200, y0 - 80, y0, [&](int a, int b) { return is(img, a, b, baseline.rgb); }), 10);
}

TEST(MetricMap, HasALegend) {
  std::vector<Pose2> poses;
  for (int k = 0; k < 40; ++k) poses.push_back({std::cos(k * 0.3) * 5, std::sin(k * 0.3) * 5, 0});
  std::vector<int> labels(40);
  for (int k = 0; k < 40; ++k) labels[static_cast<std::size_t>(k)] = k < 20 ? k : k - 20;
  const RgbImage img = trajectory_map_image({{"(a) odometry", poses}}, labels, {{25, 5}});
  // Above the plot area (y < 66): the legend's line for loop closures (light red), a place's dot and the grey
  // dot of a single visit, the start's black square.
  auto above = [&](std::array<std::uint8_t, 3> rgb) {
    return count(img, 0, img.width, 28, 62, [&](int a, int b) { return is(img, a, b, rgb, 12); });
  };
  EXPECT_GT(above({255, 150, 120}), 10) << "no loop-closure entry";
  EXPECT_GT(above(place_colour(0)), 10) << "no place-colour entry";
  EXPECT_GT(above(kSingleVisitColour), 10) << "no single-visit entry";
  EXPECT_GT(above({0, 0, 0}), 60) << "no text or start square";
}

}  // namespace
}  // namespace seqtopo::plot
