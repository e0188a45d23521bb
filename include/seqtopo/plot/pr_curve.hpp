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

RgbImage pr_curve_image(const std::vector<Curve>& curves, int width = 560, int height = 440);

}  // namespace seqtopo::plot
