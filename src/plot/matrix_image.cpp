#include "seqtopo/plot/matrix_image.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace seqtopo::plot {

RgbImage matrix_image(const DenseMatrix<float>& m, const std::vector<Polyline>& overlays,
                      const MatrixImageConfig& config) {
  if (m.empty()) return RgbImage(1, 1);
  std::vector<float> sorted = m.values;
  std::sort(sorted.begin(), sorted.end());
  float lo = sorted.front(), hi = sorted.back();
  if (config.robust_range && sorted.size() > 100) {
    lo = sorted[sorted.size() / 100];
    hi = sorted[sorted.size() - 1 - sorted.size() / 100];
  }
  const float span = hi > lo ? hi - lo : 1.0F;

  const cv::Mat values(static_cast<int>(m.rows), static_cast<int>(m.cols), CV_32F, const_cast<float*>(m.values.data()));
  cv::Mat grey;
  values.convertTo(grey, CV_8U, 255.0 / span, -lo * 255.0 / span);

  const int larger = static_cast<int>(std::max(m.rows, m.cols));
  double scale = 1.0;
  if (larger < config.min_size) scale = std::ceil(static_cast<double>(config.min_size) / larger);
  if (larger > config.max_size) scale = static_cast<double>(config.max_size) / larger;
  cv::Mat scaled;
  const cv::Size size(std::max(1, static_cast<int>(std::lround(m.cols * scale))),
                      std::max(1, static_cast<int>(std::lround(m.rows * scale))));
  cv::resize(grey, scaled, size, 0, 0, scale >= 1.0 ? cv::INTER_NEAREST : cv::INTER_AREA);
  cv::Mat rgb;
  cv::cvtColor(scaled, rgb, cv::COLOR_GRAY2RGB);

  for (const auto& line : overlays) {
    std::vector<cv::Point> pts;
    for (auto [r, c] : line.points) {
      pts.emplace_back(static_cast<int>(std::lround((c + 0.5) * scale)),
                       static_cast<int>(std::lround((r + 0.5) * scale)));
    }
    const cv::Scalar colour(line.rgb[0], line.rgb[1], line.rgb[2]);
    if (pts.size() == 1) {
      cv::circle(rgb, pts[0], std::max(1, line.thickness), colour, cv::FILLED);
    } else if (!pts.empty()) {
      cv::polylines(rgb, pts, false, colour, line.thickness, cv::LINE_AA);
    }
  }
  RgbImage out(rgb.cols, rgb.rows);
  for (int y = 0; y < rgb.rows; ++y) std::copy_n(rgb.ptr<std::uint8_t>(y), rgb.cols * 3, out.at(0, y));
  return out;
}

}  // namespace seqtopo::plot
