#include "seqtopo/plot/png.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "seqtopo/io/atomic_output.hpp"

namespace seqtopo::plot {

std::string encode_png(const RgbImage& image) {
  if (image.width <= 0 || image.height <= 0) throw std::invalid_argument("cannot encode an empty image");
  const cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.pixels.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  std::vector<std::uint8_t> bytes;
  cv::imencode(".png", bgr, bytes);
  return {bytes.begin(), bytes.end()};
}

void write_png(const std::filesystem::path& path, const RgbImage& image) {
  io::write_file_atomic(path, encode_png(image));
}

}  // namespace seqtopo::plot
