// significance/low_information.hpp: the grey-level entropy of an image against hand-worked values, and the
// frames it calls of little information, with the absolute and the relative bound.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "seqtopo/significance/low_information.hpp"

namespace seqtopo::significance {
namespace {

RgbImage grey(int w, int h, std::uint8_t level) { return RgbImage(w, h, level); }

TEST(LowInformation, EntropyOfHandWorkedImages) {
  EXPECT_DOUBLE_EQ(grey_entropy(grey(16, 8, 0)), 0.0);  // one grey level
  EXPECT_DOUBLE_EQ(grey_entropy(RgbImage()), 0.0);
  RgbImage half = grey(16, 8, 10);
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      std::uint8_t* p = half.at(x, y);
      p[0] = p[1] = p[2] = 200;
    }
  }
  EXPECT_NEAR(grey_entropy(half), 1.0, 1e-12);  // two levels, half each
  // Four levels a quarter each: 2 bits. Colour pixels count by their luma: pure red, green, blue and black.
  RgbImage four(2, 2, 0);
  four.at(0, 0)[0] = 255;
  four.at(1, 0)[1] = 255;
  four.at(0, 1)[2] = 255;
  EXPECT_NEAR(grey_entropy(four), 2.0, 1e-12);
  // Every level of 256 equally often: 8 bits.
  RgbImage all(256, 1, 0);
  for (int x = 0; x < 256; ++x) all.at(x, 0)[0] = all.at(x, 0)[1] = all.at(x, 0)[2] = static_cast<std::uint8_t>(x);
  EXPECT_NEAR(grey_entropy(all), 8.0, 1e-12);
}

TEST(LowInformation, FramesBelowBothBounds) {
  // A sequence of ordinary frames (6-7 bits) with a tunnel (1-2 bits) and a dim frame at 4.8 (above 4.5).
  const std::vector<double> entropy = {6.5, 6.8, 1.2, 1.4, 0.1, 6.9, 4.8, 6.2, 4.4, 7.0};
  EXPECT_EQ(low_information_frames(entropy), (std::vector<std::size_t>{2, 3, 4, 8}));
  // A camera whose every frame is dim keeps them; only those far below its own median are masked.
  const std::vector<double> dim = {3.6, 3.8, 3.5, 1.0, 3.9, 3.7, 0.5};
  EXPECT_EQ(low_information_frames(dim), (std::vector<std::size_t>{3, 6}));
  EXPECT_TRUE(low_information_frames({}).empty());
  EXPECT_THROW(low_information_frames(entropy, {.max_entropy = -1}), std::invalid_argument);
  EXPECT_THROW(low_information_frames(entropy, {.below_median = std::nan("")}), std::invalid_argument);
}

TEST(LowInformation, FrameFlagsMarkTheListedFramesAndNameOnePastTheSequence) {
  const std::vector<std::size_t> frames{0, 3, 4};
  EXPECT_EQ(frame_flags(frames, 6), (std::vector<bool>{true, false, false, true, true, false}));
  EXPECT_EQ(frame_flags({}, 2), (std::vector<bool>{false, false}));
  try {
    frame_flags(frames, 4, "low-information map frame");
    FAIL() << "frame 4 of 4 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "low-information map frame 4 is past the sequence's 4 frames");
  }
}

// As frames arrive: each frame judged by the batch rule on the frames so far (the last of them), whatever order
// the entropies come in (the running median against a sort each time).
TEST(LowInformation, TheStreamJudgesEachFrameByTheFramesSoFar) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 8.0);
  for (int run = 0; run < 20; ++run) {
    LowInformationStream stream;
    std::vector<double> so_far;
    const std::size_t n = 1 + static_cast<std::size_t>(run) * 13;
    for (std::size_t k = 0; k < n; ++k) {
      // Ties and runs too: a tenth of the frames repeat the previous value.
      const double e =
          k > 0 && k % 10 == 0 ? so_far.back() : (run % 2 == 0 ? u(rng) : 7.0 - 0.05 * static_cast<double>(k));
      so_far.push_back(e);
      const auto batch = low_information_frames(so_far);
      const bool expected = !batch.empty() && batch.back() == k;
      ASSERT_EQ(stream.add(e), expected) << run << ": frame " << k;
    }
  }
  EXPECT_THROW(LowInformationStream({.max_entropy = -1}), std::invalid_argument);
}

TEST(LowInformation, RandomTextureIsRichAndADarkFrameWithAFaintLightIsNot) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> level(0, 255);
  RgbImage texture(64, 32);
  for (auto& v : texture.pixels) v = static_cast<std::uint8_t>(level(rng));
  EXPECT_GT(grey_entropy(texture), 6.0);
  // Near-black with sensor noise of about 2 grey levels and a faint lamp: what a tunnel looks like.
  std::normal_distribution<double> noise(5.0, 2.0);
  RgbImage dark(64, 32);
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 64; ++x) {
      const double lamp = 20.0 * std::exp(-((x - 40) * (x - 40) + (y - 12) * (y - 12)) / 18.0);
      const auto v = static_cast<std::uint8_t>(std::clamp(noise(rng) + lamp, 0.0, 255.0));
      std::uint8_t* p = dark.at(x, y);
      p[0] = p[1] = p[2] = v;
    }
  }
  EXPECT_LT(grey_entropy(dark), 4.5);
}

}  // namespace
}  // namespace seqtopo::significance
