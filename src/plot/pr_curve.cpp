#include "seqtopo/plot/pr_curve.hpp"

#include <algorithm>
#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace seqtopo::plot {

RgbImage pr_curve_image(const std::vector<Curve>& curves, int width, int height) {
  cv::Mat img(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const int left = 60, right = 20, top = 20, bottom = 50;
  const int w = width - left - right, h = height - top - bottom;
  auto to_px = [&](double recall, double precision) {
    return cv::Point(left + static_cast<int>(recall * w), top + static_cast<int>((1.0 - precision) * h));
  };
  const cv::Scalar grey(210, 210, 210), black(0, 0, 0);
  for (int k = 0; k <= 10; ++k) {
    const double t = k / 10.0;
    cv::line(img, to_px(t, 0), to_px(t, 1), grey, 1);
    cv::line(img, to_px(0, t), to_px(1, t), grey, 1);
    char text[8];
    std::snprintf(text, sizeof text, "%.1f", t);
    if (k % 2 == 0) {
      cv::putText(img, text, to_px(t, 0) + cv::Point(-10, 18), cv::FONT_HERSHEY_SIMPLEX, 0.4, black, 1, cv::LINE_AA);
      cv::putText(img, text, to_px(0, t) + cv::Point(-30, 4), cv::FONT_HERSHEY_SIMPLEX, 0.4, black, 1, cv::LINE_AA);
    }
  }
  cv::rectangle(img, to_px(0, 1), to_px(1, 0), black, 1);
  cv::putText(img, "recall", cv::Point(left + w / 2 - 20, height - 12), cv::FONT_HERSHEY_SIMPLEX, 0.5, black, 1,
              cv::LINE_AA);
  cv::putText(img, "precision", cv::Point(4, top + 12), cv::FONT_HERSHEY_SIMPLEX, 0.4, black, 1, cv::LINE_AA);
  int legend_y = top + h - 10 - 18 * static_cast<int>(curves.size());
  for (const auto& curve : curves) {
    const cv::Scalar colour(curve.rgb[2], curve.rgb[1], curve.rgb[0]);  // BGR while drawing
    std::vector<cv::Point> pts;
    // Start the curve at recall 0 with the first precision, so a one-point curve is still a line.
    if (!curve.recall_precision.empty()) pts.push_back(to_px(0, curve.recall_precision.front().second));
    for (auto [r, p] : curve.recall_precision) pts.push_back(to_px(std::clamp(r, 0.0, 1.0), std::clamp(p, 0.0, 1.0)));
    if (pts.size() > 1) cv::polylines(img, pts, false, colour, 2, cv::LINE_AA);
    for (const auto& p : pts) cv::circle(img, p, 2, colour, cv::FILLED);
    legend_y += 18;
    cv::line(img, cv::Point(left + 12, legend_y - 4), cv::Point(left + 36, legend_y - 4), colour, 2);
    cv::putText(img, curve.label, cv::Point(left + 42, legend_y), cv::FONT_HERSHEY_SIMPLEX, 0.45, black, 1,
                cv::LINE_AA);
  }
  cv::Mat rgb;
  cv::cvtColor(img, rgb, cv::COLOR_BGR2RGB);
  RgbImage out(rgb.cols, rgb.rows);
  for (int y = 0; y < rgb.rows; ++y) std::copy_n(rgb.ptr<std::uint8_t>(y), rgb.cols * 3, out.at(0, y));
  return out;
}

}  // namespace seqtopo::plot
