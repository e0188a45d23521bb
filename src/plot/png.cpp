#include "seqtopo/plot/png.hpp"

#include <algorithm>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "seqtopo/image/codecs.hpp"
#include "seqtopo/io/atomic_output.hpp"

namespace seqtopo::plot {

std::string encode_png(const RgbImage& image) {
  if (image.width <= 0 || image.height <= 0) throw std::invalid_argument("cannot encode an empty image");
  const cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.pixels.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  const std::vector<std::uint8_t> bytes = image::codecs::encode_png(bgr);
  return {bytes.begin(), bytes.end()};
}

std::string encode_jpeg(const RgbImage& image, int quality) {
  if (image.width <= 0 || image.height <= 0) throw std::invalid_argument("cannot encode an empty image");
  const cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.pixels.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  const std::vector<std::uint8_t> bytes = image::codecs::encode_jpeg(bgr, std::clamp(quality, 1, 100));
  return {bytes.begin(), bytes.end()};
}

RgbImage shrink(const RgbImage& image, int max_side) {
  const int larger = std::max(image.width, image.height);
  if (larger <= max_side || larger <= 0 || max_side <= 0) return image;
  const double scale = static_cast<double>(max_side) / larger;
  const cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.pixels.data()));
  cv::Mat small;
  cv::resize(
      rgb, small,
      cv::Size(std::max(1, static_cast<int>(image.width * scale)), std::max(1, static_cast<int>(image.height * scale))),
      0, 0, cv::INTER_AREA);
  RgbImage out(small.cols, small.rows);
  for (int y = 0; y < small.rows; ++y) std::copy_n(small.ptr<std::uint8_t>(y), small.cols * 3, out.at(0, y));
  return out;
}

void write_png(const std::filesystem::path& path, const RgbImage& image) {
  io::write_file_atomic(path, encode_png(image));
}

}  // namespace seqtopo::plot
