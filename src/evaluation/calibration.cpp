#include "seqtopo/evaluation/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace seqtopo::evaluation {

Calibration calibration(const std::vector<double>& confidence, const std::vector<bool>& correct, std::size_t bins) {
  if (confidence.size() != correct.size()) throw std::invalid_argument("calibration: one verdict per confidence");
  if (bins == 0) throw std::invalid_argument("calibration: at least one bin");
  Calibration c;
  c.detections = confidence.size();
  c.bins.resize(bins);
  std::vector<double> sum_confidence(bins, 0), right(bins, 0);
  for (std::size_t k = 0; k < confidence.size(); ++k) {
    const double p = std::clamp(std::isfinite(confidence[k]) ? confidence[k] : 0.0, 0.0, 1.0);
    const auto b = std::min(bins - 1, static_cast<std::size_t>(p * static_cast<double>(bins)));
    ++c.bins[b].count;
    sum_confidence[b] += p;
    right[b] += correct[k] ? 1 : 0;
  }
  for (std::size_t b = 0; b < bins; ++b) {
    auto& bin = c.bins[b];
    bin.lower = static_cast<double>(b) / static_cast<double>(bins);
    bin.upper = static_cast<double>(b + 1) / static_cast<double>(bins);
    if (bin.count == 0) continue;
    const auto n = static_cast<double>(bin.count);
    bin.mean_confidence = sum_confidence[b] / n;
    bin.accuracy = right[b] / n;
    c.ece += n / static_cast<double>(c.detections) * std::abs(bin.accuracy - bin.mean_confidence);
  }
  return c;
}

}  // namespace seqtopo::evaluation
