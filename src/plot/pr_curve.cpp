#include "seqtopo/plot/pr_curve.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "axes.hpp"

namespace seqtopo::plot {
namespace {

constexpr int kLeft = 70, kRight = 20, kTop = 16, kBottom = 52;
constexpr double kPrecisionTop = 1.05;  // the axis reaches above 1: a curve at precision 1 is off the frame
constexpr double kRecallRight = 1.02;

cv::Point to_pixel(double recall, double precision, int width, int height) {
  const int w = width - kLeft - kRight, h = height - kTop - kBottom;
  return {kLeft + static_cast<int>(std::lround(recall / kRecallRight * w)),
          kTop + static_cast<int>(std::lround((kPrecisionTop - precision) / kPrecisionTop * h))};
}

// A polyline drawn in dashes of `on` pixels with gaps of `off` pixels.
void dashed_polyline(cv::Mat& img, const std::vector<cv::Point>& pts, const cv::Scalar& colour, int thickness,
                     double on = 9, double off = 5) {
  double phase = 0;  // distance travelled within the current dash+gap period
  for (std::size_t k = 1; k < pts.size(); ++k) {
    const cv::Point2d a = pts[k - 1], b = pts[k];
    const double length = std::hypot(b.x - a.x, b.y - a.y);
    double t = 0;
    while (t < length) {
      const bool drawing = phase < on;
      const double left = drawing ? on - phase : on + off - phase;
      const double step = std::min(left, length - t);
      if (drawing) {
        const cv::Point2d p = a + (b - a) * (t / length), q = a + (b - a) * ((t + step) / length);
        cv::line(img, cv::Point(cvRound(p.x), cvRound(p.y)), cv::Point(cvRound(q.x), cvRound(q.y)), colour, thickness,
                 cv::LINE_AA);
      }
      t += step;
      phase = std::fmod(phase + step, on + off);
    }
  }
}

}  // namespace

std::pair<int, int> pr_curve_pixel(double recall, double precision, int width, int height) {
  const cv::Point p = to_pixel(recall, precision, width, height);
  return {p.x, p.y};
}

RgbImage pr_curve_image(const std::vector<Curve>& curves, int width, int height) {
  using detail::kFont;
  cv::Mat img(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  auto px = [&](double r, double p) { return to_pixel(r, p, width, height); };
  const cv::Scalar grid(222, 222, 222), black(0, 0, 0);
  for (int k = 0; k <= 10; ++k) {
    const double t = k / 10.0;
    cv::line(img, px(t, 0), px(t, kPrecisionTop), grid, 1);
    cv::line(img, px(0, t), px(kRecallRight, t), grid, 1);
    cv::line(img, px(t, 0), px(t, 0) + cv::Point(0, 6), black, 1);
    cv::line(img, px(0, t), px(0, t) - cv::Point(6, 0), black, 1);
    if (k % 2 == 0) {
      char text[8];
      std::snprintf(text, sizeof text, "%.1f", t);
      int baseline = 0;
      const cv::Size size = cv::getTextSize(text, kFont, 0.42, 1, &baseline);
      cv::putText(img, text, px(t, 0) + cv::Point(-size.width / 2, 10 + size.height), kFont, 0.42, black, 1,
                  cv::LINE_AA);
      cv::putText(img, text, px(0, t) + cv::Point(-10 - size.width, size.height / 2), kFont, 0.42, black, 1,
                  cv::LINE_AA);
    }
  }
  cv::rectangle(img, px(0, kPrecisionTop), px(kRecallRight, 0), black, 1);
  const int w = width - kLeft - kRight, h = height - kTop - kBottom;
  {
    int baseline = 0;
    const cv::Size size = cv::getTextSize("recall", kFont, 0.5, 1, &baseline);
    cv::putText(img, "recall", {kLeft + w / 2 - size.width / 2, height - 10}, kFont, 0.5, black, 1, cv::LINE_AA);
    // Beside the axis, centred on it, read upwards: never on a tick label.
    detail::vertical_text(img, "precision", {14, kTop + h / 2}, 0.5, black);
  }
  // The others first (dashed), the first curve last (solid, on top).
  for (std::size_t n = curves.size(); n-- > 0;) {
    const auto& curve = curves[n];
    const cv::Scalar colour = detail::bgr(curve.rgb);
    std::vector<cv::Point> pts;
    // Start the curve at recall 0 with the first precision, so a one-point curve is still a line.
    if (!curve.recall_precision.empty())
      pts.push_back(px(0, std::clamp(curve.recall_precision.front().second, 0.0, 1.0)));
    for (auto [r, p] : curve.recall_precision) pts.push_back(px(std::clamp(r, 0.0, 1.0), std::clamp(p, 0.0, 1.0)));
    if (n == 0) {
      if (pts.size() > 1) cv::polylines(img, pts, false, colour, 3, cv::LINE_AA);
      for (const auto& p : pts) cv::circle(img, p, 3, colour, cv::FILLED, cv::LINE_AA);
    } else {
      dashed_polyline(img, pts, colour, 2);
    }
  }
  std::vector<LegendEntry> legend;
  for (std::size_t n = 0; n < curves.size(); ++n) {
    legend.push_back(
        {curves[n].label, curves[n].rgb, n == 0 ? LegendEntry::Mark::line : LegendEntry::Mark::dashed_line});
  }
  // One entry per row, bottom left inside the frame (where PR curves rarely go).
  int y = kTop + h - 8;
  for (std::size_t n = legend.size(); n-- > 0;) {
    const cv::Size size = detail::legend_size({legend[n]});
    y -= size.height - 1;
    detail::draw_legend(img, {legend[n]}, {kLeft + 10, y});
  }
  cv::Mat rgb;
  cv::cvtColor(img, rgb, cv::COLOR_BGR2RGB);
  RgbImage out(rgb.cols, rgb.rows);
  for (int row = 0; row < rgb.rows; ++row) std::copy_n(rgb.ptr<std::uint8_t>(row), rgb.cols * 3, out.at(0, row));
  return out;
}

}  // namespace seqtopo::plot
