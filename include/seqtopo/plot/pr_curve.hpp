#pragma once
// Precision-recall curves of several methods on one chart.
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "seqtopo/core/rgb_image.hpp"

namespace seqtopo::plot {

struct Curve {
  std::string label;
  std::vector<std::pair<double, double>> recall_precision;  // (recall, precision), in [0, 1]
  std::array<std::uint8_t, 3> rgb{200, 30, 30};
};

// The first curve is the method the figure is about: drawn solid and last, on top of the others (dashed), so
// that it shows where they coincide. The precision axis reaches a little above 1, so that a curve at precision
// 1.0 is drawn inside the frame, not on it; both axes are labelled beside their ticks; a legend names the curves.
RgbImage pr_curve_image(const std::vector<Curve>& curves, int width = 560, int height = 440);

// Where pr_curve_image() draws (recall, precision), in pixels of an image of that size (for tests).
std::pair<int, int> pr_curve_pixel(double recall, double precision, int width = 560, int height = 440);

}  // namespace seqtopo::plot
