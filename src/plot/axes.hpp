#pragma once
// Drawing helpers shared by the figures (OpenCV, BGR while drawing): tick steps, tick labels, text turned a
// quarter for a vertical axis label, and legends.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "seqtopo/plot/legend.hpp"

namespace seqtopo::plot::detail {

inline constexpr int kFont = 0;  // cv::FONT_HERSHEY_SIMPLEX

// 1, 2 or 5 times a power of ten, so that about `count` ticks span `range`.
double nice_step(double range, int count);
// v with as many decimals as the step needs ("0", "0.5", "1500").
std::string tick_label(double v, double step);
// Text centred at `centre`, read from bottom to top (a y-axis label).
void vertical_text(cv::Mat& canvas, const std::string& text, cv::Point centre, double scale, const cv::Scalar& colour);
// Width and height [pixels] of a legend drawn in one row.
cv::Size legend_size(const std::vector<LegendEntry>& entries, double scale = 0.42);
// Draws the entries in one row with their top-left corner at `origin`, on a white box with a grey border.
void draw_legend(cv::Mat& canvas, const std::vector<LegendEntry>& entries, cv::Point origin, double scale = 0.42);
cv::Scalar bgr(const std::array<std::uint8_t, 3>& rgb);

}  // namespace seqtopo::plot::detail
