#include "seqtopo/fingerprint/fingerprint.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace seqtopo::fingerprint {
namespace {

struct Hsv {
  double h = 0.0;  // [deg] 0..360
  double s = 0.0, v = 0.0;
};

Hsv to_hsv(double r, double g, double b) {
  const double mx = std::max({r, g, b}), mn = std::min({r, g, b}), c = mx - mn;
  Hsv out;
  out.v = mx;
  out.s = mx > 0 ? c / mx : 0.0;
  if (c > 0) {
    double h;
    if (mx == r) {
      h = std::fmod((g - b) / c, 6.0);
    } else if (mx == g) {
      h = (b - r) / c + 2.0;
    } else {
      h = (r - g) / c + 4.0;
    }
    out.h = h * 60.0;
    if (out.h < 0) out.h += 360.0;
  }
  return out;
}

// Representative HSV of each class.
Hsv class_hsv(int c) {
  if (c < 4) return {0.0, 0.0, 0.125 + 0.25 * c};
  const int hue = (c - 4) % 6;
  const bool bright = c >= 10;
  return {60.0 * hue, 0.7, bright ? 0.85 : 0.45};
}

void check(const FingerprintConfig& c) {
  if (!(c.band_top >= 0 && c.band_top < c.band_bottom && c.band_bottom <= 1)) {
    throw std::invalid_argument("fingerprint: need 0 <= band_top < band_bottom <= 1");
  }
  if (!(c.edge_min_fraction > 0 && c.edge_min_fraction <= 1) || !(c.column_majority > 0 && c.column_majority <= 1)) {
    throw std::invalid_argument("fingerprint: fractions must be in (0, 1]");
  }
  if (!(c.brightness_percentile >= 0 && c.brightness_percentile <= 1) ||
      !(c.brightness_target > 0 && c.brightness_target <= 1)) {
    throw std::invalid_argument("fingerprint: brightness_percentile must be in [0, 1] and brightness_target in (0, 1]");
  }
  if (c.edge_suppression < 0 || c.min_patch_width < 1 || !(c.edge_step > 0)) {
    throw std::invalid_argument("fingerprint: edge_step > 0, edge_suppression >= 0 and min_patch_width >= 1 needed");
  }
}

}  // namespace

int colour_class(std::uint8_t r, std::uint8_t g, std::uint8_t b, const FingerprintConfig& config) {
  const Hsv p = to_hsv(r / 255.0, g / 255.0, b / 255.0);
  if (p.s < config.saturation_min || p.v < config.value_min_colour) return std::min(3, static_cast<int>(p.v * 4.0));
  const int sector = static_cast<int>(std::floor((p.h + 30.0) / 60.0)) % 6;
  return (p.v < config.bright_value ? 4 : 10) + sector;
}

strings::ColourDistanceTable colour_class_distances() {
  std::array<std::array<double, 3>, strings::kColourClasses> xyz{};
  for (int c = 0; c < strings::kColourClasses; ++c) {
    const Hsv p = class_hsv(c);
    const double h = p.h * std::numbers::pi / 180.0;
    xyz[static_cast<std::size_t>(c)] = {p.s * p.v * std::cos(h), p.s * p.v * std::sin(h), p.v};
  }
  strings::ColourDistanceTable t{};
  double largest = 0.0;
  for (std::size_t a = 0; a < xyz.size(); ++a) {
    for (std::size_t b = 0; b < xyz.size(); ++b) {
      const double d = std::hypot(xyz[a][0] - xyz[b][0], xyz[a][1] - xyz[b][1], xyz[a][2] - xyz[b][2]);
      t[a][b] = d;
      largest = std::max(largest, d);
    }
  }
  for (auto& row : t) {
    for (double& d : row) d /= largest;
  }
  return t;
}

std::array<std::uint8_t, 3> class_colour(int c) {
  if (c < 0 || c >= strings::kColourClasses) throw std::invalid_argument("class_colour: class must be in 0..15");
  const Hsv p = class_hsv(c);
  // HSV -> RGB
  const double ch = p.v * p.s, hp = p.h / 60.0, x = ch * (1 - std::abs(std::fmod(hp, 2.0) - 1)), m = p.v - ch;
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(hp) % 6) {
    case 0:
      r = ch, g = x;
      break;
    case 1:
      r = x, g = ch;
      break;
    case 2:
      g = ch, b = x;
      break;
    case 3:
      g = x, b = ch;
      break;
    case 4:
      r = x, b = ch;
      break;
    default:
      r = ch, b = x;
      break;
  }
  auto byte = [](double v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); };
  return {byte(r + m), byte(g + m), byte(b + m)};
}

Fingerprint extract_fingerprint(const RgbImage& image, const FingerprintConfig& config) {
  check(config);
  const int w = image.width, h = image.height;
  if (w < 3 || h < 1 || image.pixels.size() != static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3) {
    throw std::invalid_argument("fingerprint: the panorama must be at least 3 pixels wide and 1 high");
  }
  const int row_begin = std::clamp(static_cast<int>(std::floor(config.band_top * h)), 0, h - 1);
  const int row_end = std::clamp(static_cast<int>(std::ceil(config.band_bottom * h)), row_begin + 1, h);
  const int rows = row_end - row_begin;
  // The step of the channel that changes most, so an edge between two colours of equal brightness counts.
  auto step = [&](int x, int y) {
    const std::uint8_t* a = image.at((x + w - 1) % w, y);
    const std::uint8_t* b = image.at((x + 1) % w, y);
    return std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
  };

  // Vertical edges: rows with a strong horizontal step, per column, then non-maximum suppression.
  std::vector<int> strong(static_cast<std::size_t>(w), 0);
  for (int x = 0; x < w; ++x) {
    for (int y = row_begin; y < row_end; ++y) strong[static_cast<std::size_t>(x)] += step(x, y) >= config.edge_step;
  }
  const int needed = static_cast<int>(std::ceil(config.edge_min_fraction * rows));
  std::vector<Feature> features;
  for (int x = 0; x < w; ++x) {
    const int s = strong[static_cast<std::size_t>(x)];
    if (s < needed) continue;
    bool peak = true;
    for (int o = -config.edge_suppression; o <= config.edge_suppression && peak; ++o) {
      if (o == 0) continue;
      const int other = strong[static_cast<std::size_t>(((x + o) % w + w) % w)];
      peak = other < s || (other == s && o > 0);  // on a plateau the first column is the edge
    }
    if (peak) features.push_back({x, 'v'});
  }

  // Brightness normalization: the same place seen under a different exposure keeps its classes when the
  // brightness percentile of the band is mapped to a fixed level.
  double gain = 1.0;
  if (config.brightness_percentile > 0) {
    std::vector<int> brightness;
    brightness.reserve(static_cast<std::size_t>(w * rows));
    for (int y = row_begin; y < row_end; ++y) {
      for (int x = 0; x < w; ++x) {
        const std::uint8_t* p = image.at(x, y);
        brightness.push_back(std::max({p[0], p[1], p[2]}));
      }
    }
    const auto k = static_cast<std::size_t>(config.brightness_percentile * static_cast<double>(brightness.size() - 1));
    std::nth_element(brightness.begin(), brightness.begin() + static_cast<std::ptrdiff_t>(k), brightness.end());
    if (brightness[k] > 0) gain = config.brightness_target * 255.0 / brightness[k];
  }
  auto scaled = [gain](std::uint8_t v) { return static_cast<std::uint8_t>(std::min(255.0, std::round(v * gain))); };

  // Colour patches: dominant class per column, then runs of one class (cyclic).
  std::vector<int> dominant(static_cast<std::size_t>(w), -1);
  for (int x = 0; x < w; ++x) {
    std::array<int, strings::kColourClasses> votes{};
    for (int y = row_begin; y < row_end; ++y) {
      const std::uint8_t* p = image.at(x, y);
      ++votes[static_cast<std::size_t>(colour_class(scaled(p[0]), scaled(p[1]), scaled(p[2]), config))];
    }
    const auto best = std::max_element(votes.begin(), votes.end());
    if (*best >= config.column_majority * rows)
      dominant[static_cast<std::size_t>(x)] = static_cast<int>(best - votes.begin());
  }
  auto at = [&](int x) { return dominant[static_cast<std::size_t>(((x % w) + w) % w)]; };
  // Start scanning just after a class change so no run is cut by the image border.
  int start = 0;
  while (start < w && at(start) == at(start - 1)) ++start;
  if (start == w) {  // one class all around (or none): a single patch at column 0
    if (at(0) >= 0 && w >= config.min_patch_width) features.push_back({0, static_cast<char>('A' + at(0))});
  } else {
    for (int x = start; x < start + w;) {
      int end = x + 1;
      while (end < start + w && at(end) == at(x)) ++end;
      if (at(x) >= 0 && end - x >= config.min_patch_width) features.push_back({x % w, static_cast<char>('A' + at(x))});
      x = end;
    }
  }
  std::stable_sort(features.begin(), features.end(), [](const Feature& a, const Feature& b) {
    return a.column < b.column || (a.column == b.column && a.symbol == 'v' && b.symbol != 'v');
  });
  Fingerprint out;
  out.features = std::move(features);
  for (const Feature& f : out.features) out.symbols.push_back(f.symbol);
  return out;
}

}  // namespace seqtopo::fingerprint
