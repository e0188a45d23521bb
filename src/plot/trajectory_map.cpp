#include "seqtopo/plot/trajectory_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <unordered_map>

#include "axes.hpp"

namespace seqtopo::plot {
namespace {

const cv::Scalar kBackground(255, 255, 255);
const cv::Scalar kAxis(0, 0, 0);
const cv::Scalar kGrid(228, 228, 228);
const cv::Scalar kPath(110, 110, 110);
const cv::Scalar kLoopPair(255, 150, 120);
const cv::Scalar kUnlabelled(200, 30, 30);  // the paper's red dots when no place labels are given
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

cv::Scalar scalar(const std::array<std::uint8_t, 3>& rgb) { return {double(rgb[0]), double(rgb[1]), double(rgb[2])}; }

using detail::nice_step;
using detail::tick_label;

// World [m] to panel pixels: equal scale in x and y, y up, the data centred in the plot area.
struct Frame {
  cv::Rect area;
  double x0 = 0, y0 = 0, scale = 1;  // world point at the area's centre [m]; [pixels/m]
  cv::Point2d to_pixel(double x, double y) const {
    return {area.x + area.width / 2.0 + (x - x0) * scale, area.y + area.height / 2.0 - (y - y0) * scale};
  }
  double world_x(double px) const { return x0 + (px - area.x - area.width / 2.0) / scale; }
  double world_y(double py) const { return y0 - (py - area.y - area.height / 2.0) / scale; }
};

Frame make_frame(const std::vector<Pose2>& poses, const cv::Rect& area) {
  double min_x = 0, max_x = 1, min_y = 0, max_y = 1;
  if (!poses.empty()) {
    min_x = max_x = poses[0].x;
    min_y = max_y = poses[0].y;
    for (const auto& p : poses) {
      min_x = std::min(min_x, p.x), max_x = std::max(max_x, p.x);
      min_y = std::min(min_y, p.y), max_y = std::max(max_y, p.y);
    }
  }
  // At least 1 m across, and a 5 % border so dots on the edge are whole.
  const double span_x = std::max(max_x - min_x, 1.0) * 1.1, span_y = std::max(max_y - min_y, 1.0) * 1.1;
  Frame f;
  f.area = area;
  f.x0 = 0.5 * (min_x + max_x);
  f.y0 = 0.5 * (min_y + max_y);
  f.scale = std::min(area.width / span_x, area.height / span_y);
  return f;
}

cv::Point pixel(const cv::Point2d& p) {
  return {static_cast<int>(std::lround(p.x)), static_cast<int>(std::lround(p.y))};
}

void draw_axes(cv::Mat& canvas, const Frame& f, const std::string& title) {
  const cv::Rect& a = f.area;
  const double left = f.world_x(a.x), right = f.world_x(a.x + a.width);
  const double bottom = f.world_y(a.y + a.height), top = f.world_y(a.y);
  const double step = nice_step(std::max(right - left, top - bottom), 6);
  for (double v = std::ceil(left / step) * step; v <= right; v += step) {
    const int px = pixel(f.to_pixel(v, 0)).x;
    cv::line(canvas, {px, a.y}, {px, a.y + a.height}, kGrid, 1);
    cv::line(canvas, {px, a.y + a.height}, {px, a.y + a.height + 5}, kAxis, 1);
    const std::string text = tick_label(v, step);
    int baseline = 0;
    const cv::Size size = cv::getTextSize(text, kFont, 0.4, 1, &baseline);
    cv::putText(canvas, text, {px - size.width / 2, a.y + a.height + 8 + size.height}, kFont, 0.4, kAxis, 1,
                cv::LINE_AA);
  }
  for (double v = std::ceil(bottom / step) * step; v <= top; v += step) {
    const int py = pixel(f.to_pixel(0, v)).y;
    cv::line(canvas, {a.x, py}, {a.x + a.width, py}, kGrid, 1);
    cv::line(canvas, {a.x - 5, py}, {a.x, py}, kAxis, 1);
    const std::string text = tick_label(v, step);
    int baseline = 0;
    const cv::Size size = cv::getTextSize(text, kFont, 0.4, 1, &baseline);
    cv::putText(canvas, text, {a.x - 8 - size.width, py + size.height / 2}, kFont, 0.4, kAxis, 1, cv::LINE_AA);
  }
  cv::rectangle(canvas, a, kAxis, 1);
  cv::putText(canvas, "x [m]", {a.x + a.width - 40, a.y + a.height + 36}, kFont, 0.45, kAxis, 1, cv::LINE_AA);
  detail::vertical_text(canvas, "y [m]", {a.x - 58, a.y + a.height / 2}, 0.45, kAxis);
  cv::putText(canvas, title, {a.x, 22}, kFont, 0.6, kAxis, 1, cv::LINE_AA);
}

}  // namespace

std::array<std::uint8_t, 3> place_colour(int label) {
  if (label < 0) return kSingleVisitColour;
  // Golden-ratio steps around the hue circle keep neighbouring labels apart; saturated, mid-bright.
  const double hue = std::fmod(static_cast<double>(label) * 0.6180339887498949, 1.0) * 6.0;  // [sextants]
  const double s = 0.85, v = 0.85;
  const double c = v * s, x = c * (1 - std::abs(std::fmod(hue, 2.0) - 1)), m = v - c;
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(hue)) {
    case 0:
      r = c, g = x;
      break;
    case 1:
      r = x, g = c;
      break;
    case 2:
      g = c, b = x;
      break;
    case 3:
      g = x, b = c;
      break;
    case 4:
      r = x, b = c;
      break;
    default:
      r = c, b = x;
      break;
  }
  auto byte = [&](double u) { return static_cast<std::uint8_t>(std::lround((u + m) * 255)); };
  return {byte(r), byte(g), byte(b)};
}

RgbImage trajectory_map_image(const std::vector<TrajectoryPanel>& panels, const std::vector<int>& labels,
                              const std::vector<std::pair<std::size_t, std::size_t>>& loop_pairs,
                              const TrajectoryMapConfig& config) {
  if (panels.empty()) throw std::invalid_argument("metric map: no panel to draw");
  if (config.panel_width < 200 || config.panel_height < 200 || config.dot_radius < 1) {
    throw std::invalid_argument("metric map: panels must be at least 200x200 pixels and dots at least 1 pixel");
  }
  for (const auto& panel : panels) {
    if (!labels.empty() && labels.size() != panel.poses.size()) {
      throw std::invalid_argument("metric map: panel '" + panel.title + "' has " + std::to_string(panel.poses.size()) +
                                  " poses but there are " + std::to_string(labels.size()) + " labels");
    }
    for (const auto& p : panel.poses) {
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
        throw std::invalid_argument("metric map: panel '" + panel.title + "' has a non-finite position");
      }
    }
    for (const auto& [i, j] : loop_pairs) {
      if (i >= panel.poses.size() || j >= panel.poses.size()) {
        throw std::invalid_argument("metric map: loop pair (" + std::to_string(i) + ", " + std::to_string(j) +
                                    ") out of range for panel '" + panel.title + "'");
      }
    }
  }
  std::unordered_map<int, int> count;
  for (int label : labels) ++count[label];

  const int w = config.panel_width, h = config.panel_height;
  cv::Mat canvas(h, w * static_cast<int>(panels.size()), CV_8UC3, kBackground);
  for (std::size_t k = 0; k < panels.size(); ++k) {
    const auto& poses = panels[k].poses;
    const int left = static_cast<int>(k) * w;
    // Room for the title and the legend above, tick labels on the left and below.
    const cv::Rect area(left + 70, 66, w - 70 - 20, h - 66 - 55);
    const Frame f = make_frame(poses, area);
    draw_axes(canvas, f, panels[k].title);

    cv::Mat plot = canvas(area);  // clip data to the plot area
    auto local = [&](const Pose2& p) {
      const cv::Point2d q = f.to_pixel(p.x, p.y);
      return pixel({q.x - area.x, q.y - area.y});
    };
    for (const auto& [i, j] : loop_pairs) cv::line(plot, local(poses[i]), local(poses[j]), kLoopPair, 1, cv::LINE_AA);
    std::vector<cv::Point> path;
    path.reserve(poses.size());
    for (const auto& p : poses) path.push_back(local(p));
    if (path.size() > 1) cv::polylines(plot, path, false, kPath, 1, cv::LINE_AA);
    // Single visits first so the revisited places are drawn on top.
    for (int pass = 0; pass < 2; ++pass) {
      for (std::size_t i = 0; i < poses.size(); ++i) {
        const bool revisited = !labels.empty() && labels[i] >= 0 && count[labels[i]] > 1;
        if (revisited != (pass == 1)) continue;
        const cv::Scalar colour = labels.empty() ? kUnlabelled
                                  : revisited    ? scalar(place_colour(labels[i]))
                                                 : scalar(kSingleVisitColour);
        cv::circle(plot, path[i], config.dot_radius, colour, cv::FILLED, cv::LINE_AA);
      }
    }
    if (!path.empty()) {
      // The start, as a hollow black square.
      const int s = config.dot_radius + 3;
      cv::rectangle(plot, cv::Rect(path[0].x - s, path[0].y - s, 2 * s + 1, 2 * s + 1), kAxis, 2);
    }
    // What the colours, lines and the square stand for. This canvas is drawn in RGB order and draw_legend()
    // swaps to BGR, so the colours are given swapped.
    auto rgb = [](const cv::Scalar& c) {
      return std::array<std::uint8_t, 3>{static_cast<std::uint8_t>(c[2]), static_cast<std::uint8_t>(c[1]),
                                         static_cast<std::uint8_t>(c[0])};
    };
    const auto first_place = place_colour(0);
    std::vector<LegendEntry> legend{{"path", rgb(kPath), LegendEntry::Mark::line}};
    if (!loop_pairs.empty()) legend.push_back({"loop closure", rgb(kLoopPair), LegendEntry::Mark::line});
    if (labels.empty()) {
      legend.push_back({"image", rgb(kUnlabelled), LegendEntry::Mark::dot});
    } else {
      legend.push_back({"revisited place (colour per place)",
                        {first_place[2], first_place[1], first_place[0]},
                        LegendEntry::Mark::dot});
      legend.push_back({"seen once", kSingleVisitColour, LegendEntry::Mark::dot});
    }
    legend.push_back({"start", {0, 0, 0}, LegendEntry::Mark::hollow_square});
    // Shrink the text until the legend fits the panel's width.
    double scale = 0.4;
    while (scale > 0.25 && detail::legend_size(legend, scale).width > w - 80) scale -= 0.03;
    detail::draw_legend(canvas, legend, {left + 70, 30}, scale);
  }

  RgbImage out(canvas.cols, canvas.rows);
  for (int y = 0; y < canvas.rows; ++y)
    std::memcpy(out.at(0, y), canvas.ptr<std::uint8_t>(y), static_cast<std::size_t>(canvas.cols) * 3);
  return out;
}

}  // namespace seqtopo::plot
