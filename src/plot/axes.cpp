#include "axes.hpp"

#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

namespace seqtopo::plot::detail {

double nice_step(double range, int count) {
  if (!(range > 0)) return 1;
  const double raw = range / count;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0}) {
    if (m * magnitude >= raw) return m * magnitude;
  }
  return 10.0 * magnitude;
}

std::string tick_label(double v, double step) {
  char buf[32];
  const int decimals = step >= 1 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
  std::snprintf(buf, sizeof buf, "%.*f", decimals, std::abs(v) < step * 1e-6 ? 0.0 : v);
  return buf;
}

void vertical_text(cv::Mat& canvas, const std::string& text, cv::Point centre, double scale, const cv::Scalar& colour) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, kFont, scale, 1, &baseline);
  cv::Mat strip(size.height + baseline + 4, size.width + 4, canvas.type(), cv::Scalar(255, 255, 255));
  cv::putText(strip, text, {2, size.height + 1}, kFont, scale, colour, 1, cv::LINE_AA);
  cv::Mat turned;
  cv::rotate(strip, turned, cv::ROTATE_90_COUNTERCLOCKWISE);
  const cv::Rect where(centre.x - turned.cols / 2, centre.y - turned.rows / 2, turned.cols, turned.rows);
  const cv::Rect inside = where & cv::Rect(0, 0, canvas.cols, canvas.rows);
  if (inside.area() == 0) return;
  // Only the text's pixels, so a white strip never covers what is under it.
  cv::Mat target = canvas(inside);
  const cv::Mat source = turned(cv::Rect(inside.x - where.x, inside.y - where.y, inside.width, inside.height));
  cv::Mat grey;
  cv::cvtColor(source, grey, cv::COLOR_BGR2GRAY);
  source.copyTo(target, grey < 250);
}

cv::Scalar bgr(const std::array<std::uint8_t, 3>& rgb) { return {double(rgb[2]), double(rgb[1]), double(rgb[0])}; }

namespace {
constexpr int kMarkWidth = 22, kGap = 6, kItemGap = 16, kPad = 6;
}

cv::Size legend_size(const std::vector<LegendEntry>& entries, double scale) {
  int width = kPad, height = 0;
  for (const auto& e : entries) {
    int baseline = 0;
    const cv::Size size = cv::getTextSize(e.label, kFont, scale, 1, &baseline);
    width += kMarkWidth + kGap + size.width + kItemGap;
    height = std::max(height, size.height + baseline);
  }
  return {width - kItemGap + kPad, height + 2 * kPad};
}

void draw_legend(cv::Mat& canvas, const std::vector<LegendEntry>& entries, cv::Point origin, double scale) {
  if (entries.empty()) return;
  const cv::Size size = legend_size(entries, scale);
  const cv::Rect box(origin, size);
  cv::rectangle(canvas, box, cv::Scalar(255, 255, 255), cv::FILLED);
  cv::rectangle(canvas, box, cv::Scalar(150, 150, 150), 1);
  int x = origin.x + kPad;
  const int mid = origin.y + size.height / 2;
  for (const auto& e : entries) {
    const cv::Scalar colour = bgr(e.rgb);
    switch (e.mark) {
      case LegendEntry::Mark::line:
        cv::line(canvas, {x, mid}, {x + kMarkWidth, mid}, colour, 2, cv::LINE_AA);
        break;
      case LegendEntry::Mark::dashed_line:
        for (int d = 0; d < kMarkWidth; d += 8)
          cv::line(canvas, {x + d, mid}, {x + d + 4, mid}, colour, 2, cv::LINE_AA);
        break;
      case LegendEntry::Mark::dot:
        cv::circle(canvas, {x + kMarkWidth / 2, mid}, 4, colour, cv::FILLED, cv::LINE_AA);
        break;
      case LegendEntry::Mark::hollow_square:
        cv::rectangle(canvas, cv::Rect(x + kMarkWidth / 2 - 5, mid - 5, 11, 11), colour, 2);
        break;
    }
    x += kMarkWidth + kGap;
    int baseline = 0;
    const cv::Size text = cv::getTextSize(e.label, kFont, scale, 1, &baseline);
    cv::putText(canvas, e.label, {x, mid + text.height / 2}, kFont, scale, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    x += text.width + kItemGap;
  }
}

}  // namespace seqtopo::plot::detail
