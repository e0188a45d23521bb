// The panorama signature: invariant to the heading (a circular shift of the panorama) and to the gain of
// the lighting, equal to an independent DFT, and still telling different places apart.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "seqtopo/image/panorama_signature.hpp"

namespace seqtopo::image {
namespace {

RgbImage random_panorama(std::mt19937& rng, int w, int h) {
  RgbImage img(w, h);
  std::uniform_int_distribution<int> u(30, 220);
  for (auto& v : img.pixels) v = static_cast<std::uint8_t>(u(rng));
  return img;
}

// The panorama turned by `columns` pixels (the robot facing another way).
RgbImage turned(const RgbImage& img, int columns) {
  RgbImage out(img.width, img.height);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const std::uint8_t* p = img.at((x + columns) % img.width, y);
      std::copy(p, p + 3, out.at(x, y));
    }
  }
  return out;
}

double l1(const std::vector<float>& a, const std::vector<float>& b) {
  double d = 0;
  for (std::size_t k = 0; k < a.size(); ++k) d += std::abs(a[k] - b[k]);
  return d;
}

TEST(PanoramaSignature, SameForEveryHeading) {
  std::mt19937 rng(7);
  const PanoramaConfig c;  // 64 columns: a 256-wide panorama shrinks by exactly 4
  const RgbImage pano = random_panorama(rng, 256, 48);
  const auto ref = panorama_signature(pano, c);
  ASSERT_EQ(ref.size(), c.dimension());
  for (int shift : {4, 64, 128, 200}) {
    const auto s = panorama_signature(turned(pano, shift), c);
    for (std::size_t k = 0; k < ref.size(); ++k) EXPECT_NEAR(s[k], ref[k], 1e-4) << "shift " << shift << " value " << k;
  }
}

TEST(PanoramaSignature, SameUnderAGainAndTintOfTheLighting) {
  std::mt19937 rng(8);
  const RgbImage pano = random_panorama(rng, 256, 48);
  RgbImage dimmer = pano;
  const double gain[3] = {0.8, 0.75, 0.7};  // darker and slightly warmer
  for (std::size_t k = 0; k < dimmer.pixels.size(); ++k) {
    dimmer.pixels[k] = static_cast<std::uint8_t>(std::lround(pano.pixels[k] * gain[k % 3]));
  }
  const auto a = panorama_signature(pano), b = panorama_signature(dimmer);
  // Luma is exactly gain-invariant (up to the rounding to 8 bits); the opponents change only a little.
  const RgbImage other = random_panorama(rng, 256, 48);
  const auto c = panorama_signature(other);
  EXPECT_LT(l1(a, b), 0.2 * l1(a, c));
}

TEST(PanoramaSignature, EqualsTheMagnitudesOfAnIndependentDft) {
  std::mt19937 rng(9);
  const PanoramaConfig c{.columns = 32, .bands = 4, .harmonics = 10, .colour = false};
  const RgbImage pano = random_panorama(rng, 96, 40);
  const auto s = panorama_signature(pano, c);
  ASSERT_EQ(s.size(), 40U);
  // Reference: OpenCV's resize and DFT of each band's luma, normalised to unit standard deviation.
  cv::Mat rgb(pano.height, pano.width, CV_8UC3, const_cast<std::uint8_t*>(pano.pixels.data()));
  cv::Mat small;
  cv::resize(rgb, small, cv::Size(32, 4), 0, 0, cv::INTER_AREA);
  small.convertTo(small, CV_32FC3);
  for (int band = 0; band < 4; ++band) {
    cv::Mat signal(1, 32, CV_64F);
    for (int x = 0; x < 32; ++x) {
      const cv::Vec3f px = small.at<cv::Vec3f>(band, x);
      signal.at<double>(0, x) = 0.299 * px[0] + 0.587 * px[1] + 0.114 * px[2];
    }
    cv::Scalar mean, sd;
    cv::meanStdDev(signal, mean, sd);
    cv::Mat spectrum;
    cv::dft(signal, spectrum, cv::DFT_COMPLEX_OUTPUT);
    for (int h = 1; h <= 10; ++h) {
      const cv::Vec2d z = spectrum.at<cv::Vec2d>(0, h);
      const double expected = std::hypot(z[0], z[1]) / sd[0] / 32.0;
      EXPECT_NEAR(s[static_cast<std::size_t>(band * 10 + h - 1)], expected, 1e-4)
          << "band " << band << " harmonic " << h;
    }
  }
}

TEST(PanoramaSignature, FlatBandsAreZeroAndBadInputThrows) {
  RgbImage flat(128, 16, 90);
  const auto s = panorama_signature(flat);
  EXPECT_EQ(std::accumulate(s.begin(), s.end(), 0.0), 0.0);
  EXPECT_THROW(panorama_signature(RgbImage{}), std::invalid_argument);
  EXPECT_THROW(panorama_signature(flat, {.columns = 16, .harmonics = 9}), std::invalid_argument);
  EXPECT_THROW(panorama_signature(flat, {.bands = 0}), std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::image
