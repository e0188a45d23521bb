#include "seqtopo/image/patch_thumbnail.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace seqtopo::image {

std::vector<float> patch_thumbnail(const RgbImage& image, const PatchConfig& config) {
  if (config.width <= 0 || config.height <= 0 || config.patch <= 0) {
    throw std::invalid_argument("patch thumbnail: width, height and patch must be positive");
  }
  if (image.width <= 0 || image.height <= 0) throw std::invalid_argument("patch thumbnail: empty image");
  // Same luma as the joint histogram.
  cv::Mat intensity(image.height, image.width, CV_32F);
  for (int y = 0; y < image.height; ++y) {
    auto* row = intensity.ptr<float>(y);
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* px = image.at(x, y);
      row[x] = static_cast<float>((77U * px[0] + 150U * px[1] + 29U * px[2] + 128U) >> 8U);
    }
  }
  cv::Mat small;
  if (image.width == config.width && image.height == config.height) {
    small = intensity;
  } else {
    const bool shrinking = config.width <= image.width && config.height <= image.height;
    cv::resize(intensity, small, cv::Size(config.width, config.height), 0, 0,
               shrinking ? cv::INTER_AREA : cv::INTER_LINEAR);
  }

  std::vector<float> out(static_cast<std::size_t>(config.width) * static_cast<std::size_t>(config.height));
  for (int py = 0; py < config.height; py += config.patch) {
    for (int px = 0; px < config.width; px += config.patch) {
      const int ye = std::min(config.height, py + config.patch), xe = std::min(config.width, px + config.patch);
      double sum = 0, sum2 = 0;
      for (int y = py; y < ye; ++y) {
        for (int x = px; x < xe; ++x) {
          const double v = small.at<float>(y, x);
          sum += v;
          sum2 += v * v;
        }
      }
      const double count = static_cast<double>((ye - py) * (xe - px));
      const double mean = sum / count;
      const double var = std::max(0.0, sum2 / count - mean * mean);
      // Below a tenth of a grey level the patch is flat: its "contrast" would be noise blown up.
      const double scale = var > 0.01 ? 1.0 / std::sqrt(var) : 0.0;
      for (int y = py; y < ye; ++y) {
        for (int x = px; x < xe; ++x) {
          const double z = (small.at<float>(y, x) - mean) * scale;
          out[static_cast<std::size_t>(y) * static_cast<std::size_t>(config.width) + static_cast<std::size_t>(x)] =
              static_cast<float>(std::clamp(std::nearbyint(z * kPatchGrid), -127.0, 127.0) / kPatchGrid);
        }
      }
    }
  }
  return out;
}

}  // namespace seqtopo::image
