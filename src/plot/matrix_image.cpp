#include "seqtopo/plot/matrix_image.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "axes.hpp"
#include "seqtopo/image/codecs.hpp"

namespace seqtopo::plot {
namespace {

cv::Mat grey_levels(const DenseMatrix<float>& m, ValueRange range) {
  const float span = range.hi > range.lo ? range.hi - range.lo : 1.0F;
  const cv::Mat values(static_cast<int>(m.rows), static_cast<int>(m.cols), CV_32F, const_cast<float*>(m.values.data()));
  cv::Mat grey;
  values.convertTo(grey, CV_8U, 255.0 / span, -range.lo * 255.0 / span);
  return grey;
}

RgbImage to_rgb_image(const cv::Mat& bgr_or_rgb) {
  RgbImage out(bgr_or_rgb.cols, bgr_or_rgb.rows);
  for (int y = 0; y < bgr_or_rgb.rows; ++y)
    std::copy_n(bgr_or_rgb.ptr<std::uint8_t>(y), bgr_or_rgb.cols * 3, out.at(0, y));
  return out;
}

}  // namespace

ValueRange display_range(const DenseMatrix<float>& m, bool robust) {
  if (m.empty()) return {};
  if (!robust) {
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (float v : m.values) {
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    }
    if (lo > hi) return {};
    return {lo, hi};
  }
  // Above kDisplayRangeSample values the percentiles are those of every stride-th value: a display range needs
  // no exact selection over 13 million values. A stride coprime to the row length visits every column.
  std::size_t stride = 1;
  if (m.values.size() > kDisplayRangeSample) {
    stride = (m.values.size() + kDisplayRangeSample - 1) / kDisplayRangeSample;
    while (std::gcd(stride, m.cols) != 1) ++stride;
  }
  std::vector<float> sorted;
  sorted.reserve(m.values.size() / stride + 1);
  for (std::size_t k = 0; k < m.values.size(); k += stride) {
    if (std::isfinite(m.values[k])) sorted.push_back(m.values[k]);
  }
  if (sorted.empty()) return {};
  if (sorted.size() > 100) {
    // The two percentiles by selection, not a sort.
    const auto lo = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 100);
    const auto hi = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() - 1 - sorted.size() / 100);
    std::nth_element(sorted.begin(), lo, sorted.end());
    std::nth_element(lo + 1, hi, sorted.end());
    return {*lo, *hi};
  }
  const auto [lo, hi] = std::minmax_element(sorted.begin(), sorted.end());
  return {*lo, *hi};
}

namespace {

RgbImage matrix_image_in(const DenseMatrix<float>& m, const std::vector<Polyline>& overlays,
                         const MatrixImageConfig& config, ValueRange range) {
  if (m.empty()) return RgbImage(1, 1);
  const cv::Mat grey = grey_levels(m, range);

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
  return to_rgb_image(rgb);
}

}  // namespace

RgbImage matrix_image(const DenseMatrix<float>& m, const std::vector<Polyline>& overlays,
                      const MatrixImageConfig& config) {
  return matrix_image_in(m, overlays, config, display_range(m, config.robust_range));
}

namespace {

cv::Mat reduced_grey(const DenseMatrix<float>& m, ValueRange range, int max_size) {
  cv::Mat grey = grey_levels(m, range);
  const int larger = static_cast<int>(std::max(m.rows, m.cols));
  if (larger > max_size) {
    const double scale = static_cast<double>(max_size) / larger;
    cv::Mat reduced;
    cv::resize(grey, reduced,
               cv::Size(std::max(1, static_cast<int>(std::lround(m.cols * scale))),
                        std::max(1, static_cast<int>(std::lround(m.rows * scale)))),
               0, 0, cv::INTER_AREA);
    grey = reduced;
  }
  return grey;
}

}  // namespace

std::string matrix_grey_png(const DenseMatrix<float>& m, ValueRange range, int max_size) {
  if (m.empty()) return {};
  const std::vector<std::uint8_t> bytes = image::codecs::encode_png(reduced_grey(m, range, max_size));
  return {bytes.begin(), bytes.end()};
}

std::string matrix_grey_jpeg(const DenseMatrix<float>& m, ValueRange range, int max_size) {
  if (m.empty()) return {};
  const std::vector<std::uint8_t> bytes = image::codecs::encode_jpeg(reduced_grey(m, range, max_size), 90);
  return {bytes.begin(), bytes.end()};
}

RgbImage matrix_figure(const DenseMatrix<float>& m, const std::vector<Polyline>& overlays,
                       const MatrixFigureConfig& config) {
  using detail::kFont;
  const ValueRange range = display_range(m, config.image.robust_range);
  const RgbImage core = matrix_image_in(m, overlays, config.image, range);
  const double rows = static_cast<double>(config.rows ? config.rows : m.rows * config.block);
  const double cols = static_cast<double>(config.cols ? config.cols : m.cols * config.block);
  const cv::Size legend = detail::legend_size(config.legend);
  const int top = config.title.empty() ? 14 : 38, left = 78, right = 118;
  const int bottom = 56 + (config.legend.empty() ? 0 : legend.height + 10);
  const int w = core.width, h = core.height;
  const int width = std::max(left + w + right, left + legend.width + 10);
  cv::Mat canvas(top + h + bottom, width, CV_8UC3, cv::Scalar(255, 255, 255));
  // The matrix (RGB in core: swap to BGR while drawing).
  const cv::Mat rgb(h, w, CV_8UC3, const_cast<std::uint8_t*>(core.pixels.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  bgr.copyTo(canvas(cv::Rect(left, top, w, h)));
  const cv::Scalar black(0, 0, 0);
  cv::rectangle(canvas, cv::Rect(left - 1, top - 1, w + 2, h + 2), black, 1);

  // Index ticks: a tick at index v sits at the start of its cell.
  const double step = detail::nice_step(std::max(rows, cols), 6);
  for (double v = 0; v <= cols + 1e-9; v += step) {
    const int x = left + static_cast<int>(std::lround(v / cols * w));
    cv::line(canvas, {x, top + h + 1}, {x, top + h + 7}, black, 1);
    const std::string text = detail::tick_label(v, step);
    int baseline = 0;
    const cv::Size size = cv::getTextSize(text, kFont, 0.42, 1, &baseline);
    cv::putText(canvas, text, {x - size.width / 2, top + h + 10 + size.height}, kFont, 0.42, black, 1, cv::LINE_AA);
  }
  for (double v = 0; v <= rows + 1e-9; v += step) {
    const int y = top + static_cast<int>(std::lround(v / rows * h));
    cv::line(canvas, {left - 8, y}, {left - 2, y}, black, 1);
    const std::string text = detail::tick_label(v, step);
    int baseline = 0;
    const cv::Size size = cv::getTextSize(text, kFont, 0.42, 1, &baseline);
    cv::putText(canvas, text, {left - 11 - size.width, y + size.height / 2}, kFont, 0.42, black, 1, cv::LINE_AA);
  }
  {
    int baseline = 0;
    const cv::Size size = cv::getTextSize(config.column_label, kFont, 0.5, 1, &baseline);
    cv::putText(canvas, config.column_label, {left + w / 2 - size.width / 2, top + h + 44}, kFont, 0.5, black, 1,
                cv::LINE_AA);
    detail::vertical_text(canvas, config.row_label, {14, top + h / 2}, 0.5, black);
  }
  if (!config.title.empty()) cv::putText(canvas, config.title, {left, 24}, kFont, 0.55, black, 1, cv::LINE_AA);

  // Colour bar: the grey level of every value from hi (top) to lo (bottom), with value ticks.
  const int bar_x = left + w + 16, bar_w = 16, bar_h = std::max(60, std::min(h, 400));
  const int bar_y = top + (h - bar_h) / 2;
  for (int y = 0; y < bar_h; ++y) {
    const double t = 1.0 - static_cast<double>(y) / std::max(1, bar_h - 1);
    const auto g = static_cast<int>(std::lround(255 * t));
    cv::line(canvas, {bar_x, bar_y + y}, {bar_x + bar_w - 1, bar_y + y}, cv::Scalar(g, g, g), 1);
  }
  cv::rectangle(canvas, cv::Rect(bar_x - 1, bar_y - 1, bar_w + 2, bar_h + 2), black, 1);
  const double span = range.hi > range.lo ? range.hi - range.lo : 1.0;
  const double value_step = detail::nice_step(span, 6);
  for (double v = std::ceil(range.lo / value_step) * value_step; v <= range.hi + 1e-9 * span; v += value_step) {
    const int y = bar_y + static_cast<int>(std::lround((range.hi - v) / span * (bar_h - 1)));
    cv::line(canvas, {bar_x + bar_w + 1, y}, {bar_x + bar_w + 5, y}, black, 1);
    cv::putText(canvas, detail::tick_label(v, value_step), {bar_x + bar_w + 8, y + 4}, kFont, 0.4, black, 1,
                cv::LINE_AA);
  }
  detail::vertical_text(canvas, config.value_label, {bar_x + bar_w + 64, bar_y + bar_h / 2}, 0.45, black);

  detail::draw_legend(canvas, config.legend, {left, top + h + 56});
  cv::Mat out;
  cv::cvtColor(canvas, out, cv::COLOR_BGR2RGB);
  return to_rgb_image(out);
}

}  // namespace seqtopo::plot
