// Every per-pixel feature of the joint histogram against a slow, literal implementation of its definition
// (joint_histogram.hpp), on small random images of every shape, fixed seeds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "seqtopo/image/joint_histogram.hpp"

namespace seqtopo::image {
namespace {

struct Naive {
  const RgbImage& img;
  int luma(int x, int y) const {  // replicated border: the nearest pixel inside
    x = std::clamp(x, 0, img.width - 1);
    y = std::clamp(y, 0, img.height - 1);
    const std::uint8_t* p = img.at(x, y);
    return (77 * p[0] + 150 * p[1] + 29 * p[2] + 128) / 256;
  }
  std::int32_t gradient2(int x, int y) const {
    const int gx = luma(x + 1, y - 1) + 2 * luma(x + 1, y) + luma(x + 1, y + 1) - luma(x - 1, y - 1) -
                   2 * luma(x - 1, y) - luma(x - 1, y + 1);
    const int gy = luma(x - 1, y + 1) + 2 * luma(x, y + 1) + luma(x + 1, y + 1) - luma(x - 1, y - 1) -
                   2 * luma(x, y - 1) - luma(x + 1, y - 1);
    return gx * gx + gy * gy;
  }
  bool edge(int x, int y, const JointHistogramConfig& c) const {
    x = std::clamp(x, 0, img.width - 1);
    y = std::clamp(y, 0, img.height - 1);
    return std::sqrt(static_cast<double>(gradient2(x, y))) > c.edge_threshold;
  }
  int edge_count(int x, int y, const JointHistogramConfig& c) const {
    int n = 0;
    for (int dy = -2; dy <= 2; ++dy) {
      for (int dx = -2; dx <= 2; ++dx) n += edge(x + dx, y + dy, c) ? 1 : 0;
    }
    return n;
  }
  int texturedness(int x, int y, const JointHistogramConfig& c) const {
    int n = 0;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if ((dx != 0 || dy != 0) && std::abs(luma(x + dx, y + dy) - luma(x, y)) > c.texture_threshold) ++n;
      }
    }
    return n;
  }
  int rank(int x, int y) const {
    int n = 0;
    for (int dy = -2; dy <= 2; ++dy) {
      for (int dx = -2; dx <= 2; ++dx) n += luma(x + dx, y + dy) < luma(x, y) ? 1 : 0;
    }
    return n;
  }
  std::uint32_t bin(int x, int y, const JointHistogramConfig& c) const {
    const double m = std::sqrt(static_cast<double>(gradient2(x, y)));
    int g = 0;
    while (g < 4 && m >= c.gradient_edges[static_cast<std::size_t>(g)]) ++g;
    const int count = edge_count(x, y, c);
    int e = 0;
    while (e < 3 && count >= c.edge_density_edges[static_cast<std::size_t>(e)]) ++e;
    const int tx = texturedness(x, y, c);
    int t = 0;
    while (t < 3 && tx >= c.texture_edges[static_cast<std::size_t>(t)]) ++t;
    const int r = static_cast<int>(std::floor(rank(x, y) * 4.0 / 25.0));
    const std::uint8_t* p = img.at(x, y);
    const int digits[7] = {e, g, t, r, p[0] / 64, p[1] / 64, p[2] / 64};
    const int radix[7] = {4, 5, 4, 4, 4, 4, 4};
    std::uint32_t index = 0;
    for (int k = 0; k < 7; ++k)
      index = index * static_cast<std::uint32_t>(radix[k]) + static_cast<std::uint32_t>(digits[k]);
    return index;
  }
};

// Mixes noise of several amplitudes with smooth ramps and flat blocks, so that every bin range is visited.
RgbImage random_image(std::mt19937& rng, int w, int h) {
  RgbImage img(w, h);
  std::uniform_int_distribution<int> byte(0, 255), amp(0, 4);
  const int amplitude[5] = {0, 3, 12, 40, 255};
  const int a = amplitude[amp(rng)];
  const int base_r = byte(rng), base_g = byte(rng), base_b = byte(rng);
  const int slope = byte(rng) % 30;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = img.at(x, y);
      const int ramp = (x * slope) / 4;
      const int noise = a == 0 ? 0 : byte(rng) % (a + 1) - a / 2;
      p[0] = static_cast<std::uint8_t>(std::clamp(base_r + ramp + noise, 0, 255));
      p[1] = static_cast<std::uint8_t>(std::clamp(base_g + noise + (y % 7 == 0 ? 60 : 0), 0, 255));
      p[2] = static_cast<std::uint8_t>(std::clamp(base_b - ramp + noise, 0, 255));
    }
  }
  return img;
}

JointHistogramConfig random_config(std::mt19937& rng, int trial) {
  JointHistogramConfig c;
  if (trial % 3 == 0) return c;  // the documented defaults, most of the time
  std::uniform_int_distribution<int> small(0, 40);
  int g = small(rng);
  for (auto& e : c.gradient_edges) e = (g += 1 + small(rng) * 3);
  c.edge_threshold = small(rng) * 5;
  c.texture_threshold = small(rng);
  int d = 0;
  for (auto& e : c.edge_density_edges) e = (d += 1 + small(rng) % 8);
  int t = 0;
  for (auto& e : c.texture_edges) e = (t += 1 + small(rng) % 3);
  return c;
}

TEST(JointFeatures, EveryFeatureMatchesNaiveDefinition) {
  std::mt19937 rng(41);
  const std::pair<int, int> sizes[] = {{1, 1}, {1, 7}, {7, 1}, {2, 2}, {3, 2}, {5, 5}, {17, 13}, {32, 9}, {40, 31}};
  int trial = 0;
  for (int round = 0; round < 6; ++round) {
    for (auto [w, h] : sizes) {
      const RgbImage img = random_image(rng, w, h);
      const JointHistogramConfig c = random_config(rng, trial++);
      const JointFeatures f = joint_features(img, c);
      const Naive naive{img};
      ASSERT_EQ(f.width, w);
      ASSERT_EQ(f.height, h);
      for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
          const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
          SCOPED_TRACE(::testing::Message() << w << "x" << h << " pixel (" << x << ", " << y << ") trial " << trial);
          ASSERT_EQ(f.intensity[i], naive.luma(x, y));
          ASSERT_EQ(f.gradient2[i], naive.gradient2(x, y));
          ASSERT_EQ(f.edge_count[i], naive.edge_count(x, y, c));
          ASSERT_EQ(f.texturedness[i], naive.texturedness(x, y, c));
          ASSERT_EQ(f.rank[i], naive.rank(x, y));
          ASSERT_EQ(f.bin[i], naive.bin(x, y, c));
          const std::uint8_t* p = img.at(x, y);
          ASSERT_EQ(f.bin[i],
                    joint_bin(f.edge_count[i], f.gradient2[i], f.texturedness[i], f.rank[i], p[0], p[1], p[2], c));
        }
      }
    }
  }
}

TEST(JointFeatures, BinsCoverTheirRanges) {
  // Over many random images every value of every quantised feature occurs: the test above saw them all.
  std::mt19937 rng(42);
  std::vector<int> seen_e(4), seen_g(5), seen_t(4), seen_r(4);
  for (int k = 0; k < 40; ++k) {
    const JointFeatures f = joint_features(random_image(rng, 24, 24));
    for (std::uint16_t b : f.bin) {
      unsigned v = b >> 6U;  // drop the colour digits
      ++seen_r[v % 4];
      v /= 4;
      ++seen_t[v % 4];
      v /= 4;
      ++seen_g[v % 5];
      v /= 5;
      ++seen_e[v];
    }
  }
  for (const auto* seen : {&seen_e, &seen_g, &seen_t, &seen_r}) {
    for (int count : *seen) EXPECT_GT(count, 0);
  }
}

TEST(JointHistogram, NormalisedCountsOfTheBins) {
  std::mt19937 rng(43);
  for (int trial = 0; trial < 20; ++trial) {
    const RgbImage img = random_image(rng, 1 + static_cast<int>(rng() % 30), 1 + static_cast<int>(rng() % 30));
    const auto h = joint_histogram(img);
    const auto f = joint_features(img);
    EXPECT_EQ(h.dimension, 20480U);
    EXPECT_NO_THROW(h.validate());
    std::vector<float> expected(20480, 0.0F);
    for (std::uint16_t b : f.bin) expected[b] += 1.0F;
    for (auto& v : expected) v /= static_cast<float>(f.bin.size());
    const auto dense = h.to_dense();
    double sum = 0;
    for (std::size_t k = 0; k < dense.size(); ++k) {
      EXPECT_FLOAT_EQ(dense[k], expected[k]);
      sum += dense[k];
    }
    EXPECT_NEAR(sum, 1.0, 1e-5);
  }
}

TEST(JointHistogram, Misuse) {
  EXPECT_THROW(joint_histogram(RgbImage{}), std::invalid_argument);
  JointHistogramConfig c;
  c.gradient_edges = {10, 5, 20, 30};
  EXPECT_THROW(joint_histogram(RgbImage(4, 4), c), std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::image
