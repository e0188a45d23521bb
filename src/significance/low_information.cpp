#include "seqtopo/significance/low_information.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace seqtopo::significance {

double grey_entropy(const RgbImage& image) {
  const std::size_t pixels = static_cast<std::size_t>(std::max(image.width, 0)) * std::max(image.height, 0);
  if (pixels == 0 || image.pixels.size() < pixels * 3) return 0;
  std::array<std::size_t, 256> count{};
  for (std::size_t k = 0; k < pixels; ++k) {
    const std::uint8_t* p = image.pixels.data() + 3 * k;
    // BT.601 luma in integers (weights sum to 1000), rounded.
    ++count[(299U * p[0] + 587U * p[1] + 114U * p[2] + 500U) / 1000U];
  }
  double h = 0;
  for (std::size_t c : count) {
    if (c == 0) continue;
    const double q = static_cast<double>(c) / static_cast<double>(pixels);
    h -= q * std::log2(q);
  }
  return h;
}

namespace {
void check(const LowInformationConfig& config) {
  for (double v : {config.max_entropy, config.below_median}) {
    if (!std::isfinite(v) || v < 0) throw std::invalid_argument("low-information bounds must be finite and >= 0");
  }
}
}  // namespace

std::vector<bool> frame_flags(std::span<const std::size_t> frames, std::size_t n, const char* what) {
  std::vector<bool> flags(n, false);
  for (std::size_t f : frames) {
    if (f >= n) {
      throw std::invalid_argument(std::string(what) + " " + std::to_string(f) + " is past the sequence's " +
                                  std::to_string(n) + " frames");
    }
    flags[f] = true;
  }
  return flags;
}

std::vector<std::size_t> low_information_frames(std::span<const double> entropy, const LowInformationConfig& config) {
  check(config);
  if (entropy.empty()) return {};
  std::vector<double> sorted(entropy.begin(), entropy.end());
  const auto mid = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), mid, sorted.end());
  const double bound = std::min(config.max_entropy, *mid - config.below_median);
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < entropy.size(); ++k) {
    if (entropy[k] < bound) out.push_back(k);
  }
  return out;
}

LowInformationStream::LowInformationStream(const LowInformationConfig& config) : config_(config) { check(config); }

bool LowInformationStream::add(double entropy) {
  entropies_.add(entropy);
  return entropy < std::min(config_.max_entropy, entropies_.median() - config_.below_median);
}

}  // namespace seqtopo::significance
