// Patch-normalised thumbnails: size, normalisation, invariance to brightness and contrast.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "seqtopo/image/patch_thumbnail.hpp"

namespace seqtopo::image {
namespace {

RgbImage random_grey(std::mt19937& rng, int w, int h, double gain = 1.0, double offset = 0.0,
                     std::vector<int>* values = nullptr) {
  RgbImage img(w, h);
  std::uniform_int_distribution<int> u(40, 140);
  std::size_t k = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x, ++k) {
      int v = 0;
      if (values && k < values->size()) {
        v = (*values)[k];
      } else {
        v = u(rng);
        if (values) values->push_back(v);
      }
      const auto out = static_cast<std::uint8_t>(std::lround(v * gain + offset));
      std::uint8_t* p = img.at(x, y);
      p[0] = p[1] = p[2] = out;
    }
  }
  return img;
}

TEST(PatchThumbnail, EveryPatchHasMeanZeroAndUnitDeviation) {
  std::mt19937 rng(51);
  const PatchConfig c{.width = 20, .height = 12, .patch = 8};  // border patches are 4 wide / 4 high
  const auto t = patch_thumbnail(random_grey(rng, 100, 60), c);
  ASSERT_EQ(t.size(), 240U);
  for (int py = 0; py < 12; py += 8) {
    for (int px = 0; px < 20; px += 8) {
      double sum = 0, sum2 = 0;
      int n = 0;
      for (int y = py; y < std::min(12, py + 8); ++y) {
        for (int x = px; x < std::min(20, px + 8); ++x, ++n) {
          const double v = t[static_cast<std::size_t>(y * 20 + x)];
          // On the 1/16 grid within +-127/16, which the distance's byte kernel needs.
          EXPECT_EQ(v * kPatchGrid, std::nearbyint(v * kPatchGrid));
          EXPECT_LE(std::fabs(v * kPatchGrid), 127.0);
          sum += v;
          sum2 += v * v;
        }
      }
      // Rounding to the grid moves each value by at most half a step (1/32).
      EXPECT_NEAR(sum / n, 0.0, 0.5 / kPatchGrid);
      EXPECT_NEAR(sum2 / n, 1.0, 0.02);
    }
  }
}

TEST(PatchThumbnail, InvariantToBrightnessAndContrast) {
  std::mt19937 rng(52);
  std::vector<int> values;
  const auto a = patch_thumbnail(random_grey(rng, 64, 32, 1.0, 0.0, &values));
  const auto b = patch_thumbnail(random_grey(rng, 64, 32, 1.5, 30.0, &values));
  ASSERT_EQ(a.size(), b.size());
  double worst = 0;
  for (std::size_t k = 0; k < a.size(); ++k) worst = std::max(worst, static_cast<double>(std::fabs(a[k] - b[k])));
  EXPECT_LE(worst, 1.0 / kPatchGrid);  // the 8-bit image and the 1/16 grid: at most one step apart
}

TEST(PatchThumbnail, FlatImageGivesZerosAndMisuseThrows) {
  const auto t = patch_thumbnail(RgbImage(64, 32, 90));
  for (float v : t) EXPECT_EQ(v, 0.0F);
  EXPECT_THROW(patch_thumbnail(RgbImage{}), std::invalid_argument);
  EXPECT_THROW(patch_thumbnail(RgbImage(4, 4), PatchConfig{.width = 0, .height = 4, .patch = 2}),
               std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::image
