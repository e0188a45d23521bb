#include "seqtopo/image/panorama_signature.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace seqtopo::image {

std::vector<float> panorama_signature(const RgbImage& image, const PanoramaConfig& config) {
  if (config.columns < 2 || config.bands < 1 || config.harmonics < 1 || 2 * config.harmonics > config.columns) {
    throw std::invalid_argument("panorama signature: need columns >= 2, bands >= 1, 1 <= harmonics <= columns / 2");
  }
  if (image.width <= 0 || image.height <= 0) throw std::invalid_argument("panorama signature: empty image");
  cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.pixels.data()));
  cv::Mat small;
  cv::resize(rgb, small, cv::Size(config.columns, config.bands), 0, 0, cv::INTER_AREA);
  small.convertTo(small, CV_32FC3);

  const int channels = config.channels();
  const auto n = static_cast<std::size_t>(config.columns);
  std::vector<float> out;
  out.reserve(config.dimension());
  std::vector<double> signal(n);
  // Twiddle factors once per call: columns is small.
  std::vector<double> cosines(n), sines(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double angle = 2.0 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(n);
    cosines[k] = std::cos(angle);
    sines[k] = std::sin(angle);
  }
  for (int band = 0; band < config.bands; ++band) {
    const auto* row = small.ptr<cv::Vec3f>(band);
    for (int channel = 0; channel < channels; ++channel) {
      double sum = 0, sum2 = 0;
      for (std::size_t x = 0; x < n; ++x) {
        const cv::Vec3f& px = row[x];
        const double v = channel == 0   ? 0.299 * px[0] + 0.587 * px[1] + 0.114 * px[2]
                         : channel == 1 ? px[0] - px[1]
                                        : 0.5 * (px[0] + px[1]) - px[2];
        signal[x] = v;
        sum += v;
        sum2 += v * v;
      }
      const double mean = sum / static_cast<double>(n);
      const double var = std::max(0.0, sum2 / static_cast<double>(n) - mean * mean);
      // Below a tenth of a grey level the band is flat: its normalised shape would be noise.
      const double scale = var > 0.01 ? 1.0 / std::sqrt(var) : 0.0;
      for (int h = 1; h <= config.harmonics; ++h) {
        double re = 0, im = 0;
        for (std::size_t x = 0; x < n; ++x) {
          const std::size_t k = (static_cast<std::size_t>(h) * x) % n;
          re += (signal[x] - mean) * cosines[k];
          im -= (signal[x] - mean) * sines[k];
        }
        out.push_back(static_cast<float>(std::hypot(re, im) * scale / static_cast<double>(n)));
      }
    }
  }
  return out;
}

}  // namespace seqtopo::image
