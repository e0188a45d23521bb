// Fingerprints of small synthetic panoramas whose features are known.
#include <gtest/gtest.h>

#include <random>

#include "seqtopo/fingerprint/fingerprint.hpp"

namespace seqtopo::fingerprint {
namespace {

// A 360 x 40 panorama: vertical stripes [begin, end) of the given classes on a ceiling/floor background.
struct Stripe {
  int begin, end, colour_class;
};

RgbImage panorama(const std::vector<Stripe>& stripes, int background, double noise = 0.0, unsigned seed = 1) {
  RgbImage img(360, 40);
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, noise);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      int c = background;
      for (const auto& s : stripes) {
        if (x >= s.begin && x < s.end) c = s.colour_class;
      }
      if (y < 4 || y >= 36) c = 2;  // ceiling and floor bands are outside the scanned rows
      const auto rgb = class_colour(c);
      for (int k = 0; k < 3; ++k) {
        img.at(x, y)[k] = static_cast<std::uint8_t>(
            std::clamp(rgb[static_cast<std::size_t>(k)] + (noise > 0 ? n(rng) : 0.0), 0.0, 255.0));
      }
    }
  }
  return img;
}

TEST(ColourClasses, RepresentativeColoursClassifyToThemselves) {
  for (int c = 0; c < strings::kColourClasses; ++c) {
    const auto rgb = class_colour(c);
    EXPECT_EQ(colour_class(rgb[0], rgb[1], rgb[2]), c) << "class " << c;
  }
  EXPECT_EQ(colour_class(0, 0, 0), 0);
  EXPECT_EQ(colour_class(255, 255, 255), 3);
  EXPECT_EQ(colour_class(250, 10, 10), 10);    // bright red 'K'
  EXPECT_EQ(colour_class(10, 10, 90), 4 + 4);  // dark blue 'I'
}

TEST(ColourClasses, DistancesAreAValidCostTable) {
  const auto t = colour_class_distances();
  strings::EditCosts costs;
  costs.colour_distance = t;
  EXPECT_NO_THROW(strings::validate(costs));
  // Neighbouring hues are closer than opposite ones, light grey closer to white than to black.
  EXPECT_LT(t[10][11], t[10][13]);
  EXPECT_LT(t[2][3], t[2][0]);
  EXPECT_GT(costs.substitution('K', 'N'), costs.substitution('K', 'L'));
  EXPECT_EQ(costs.substitution('K', 'v'), costs.discordance);
}

TEST(Fingerprint, StripesGiveEdgesAndPatches) {
  // Light grey wall 'C' with a bright green panel 'M' and a dark blue door 'I'.
  const auto img = panorama({{60, 100, 12}, {200, 230, 8}}, 2);
  const auto f = extract_fingerprint(img);
  // The wall run 230..59 crosses the border, so it is listed at column 230.
  EXPECT_EQ(f.symbols, "vMvCvIvC");
  ASSERT_EQ(f.features.size(), 8U);
  EXPECT_EQ(f.features[0].column, 59);  // columns 59 and 60 both straddle the step: the first one is the edge
  EXPECT_EQ(f.features[1].column, 60);
}

TEST(Fingerprint, RobustToSensorNoise) {
  const auto clean = extract_fingerprint(panorama({{60, 100, 12}, {200, 230, 8}}, 2));
  for (unsigned seed = 1; seed <= 5; ++seed) {
    EXPECT_EQ(extract_fingerprint(panorama({{60, 100, 12}, {200, 230, 8}}, 2, 3.0, seed)).symbols, clean.symbols);
  }
}

TEST(Fingerprint, ExposureDoesNotChangeTheString) {
  const auto img = panorama({{60, 100, 12}, {200, 230, 8}, {280, 320, 3}}, 2);
  const std::string reference = extract_fingerprint(img).symbols;
  for (double gain : {0.8, 0.9, 1.1}) {
    RgbImage dimmed = img;
    for (auto& v : dimmed.pixels) v = static_cast<std::uint8_t>(std::min(255.0, std::round(v * gain)));
    EXPECT_EQ(extract_fingerprint(dimmed).symbols, reference) << "gain " << gain;
  }
  FingerprintConfig bad;
  bad.brightness_percentile = 1.5;
  EXPECT_THROW(extract_fingerprint(img, bad), std::invalid_argument);
}

TEST(Fingerprint, RotatingThePanoramaRotatesTheString) {
  const auto img = panorama({{10, 40, 12}, {100, 180, 8}, {250, 300, 15}}, 1);
  RgbImage turned(img.width, img.height);
  const int shift = 90;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) std::copy_n(img.at((x + shift) % img.width, y), 3, turned.at(x, y));
  }
  const std::string a = extract_fingerprint(img).symbols, b = extract_fingerprint(turned).symbols;
  ASSERT_EQ(a.size(), b.size());
  EXPECT_NE((a + a).find(b), std::string::npos) << a << " vs " << b;
}

TEST(Fingerprint, PatchAcrossTheBorderIsOnePatch) {
  const auto f = extract_fingerprint(panorama({{0, 20, 12}, {340, 360, 12}}, 2));
  EXPECT_EQ(f.symbols, "vCvM");  // the green run 340..19 starts at column 340
}

TEST(Fingerprint, UniformPanoramaAndMisuse) {
  FingerprintConfig raw;
  raw.brightness_percentile = 0;  // without normalization a dark magenta wall stays dark
  EXPECT_EQ(extract_fingerprint(panorama({}, 9), raw).symbols, "J");
  EXPECT_THROW(extract_fingerprint(RgbImage{}), std::invalid_argument);
  FingerprintConfig bad;
  bad.band_top = 0.9;
  bad.band_bottom = 0.1;
  EXPECT_THROW(extract_fingerprint(panorama({}, 1), bad), std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::fingerprint
