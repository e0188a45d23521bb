#include "seqtopo/mapping/odometry_gate.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace seqtopo::mapping {

std::vector<bool> consistent_with_odometry(const std::vector<align::LocalAlignment>& alignments,
                                           std::span<const Pose2> odometry, const OdometryGate& gate) {
  const auto bad = [](double v) { return std::isnan(v) || v < 0; };
  if (bad(gate.base) || bad(gate.drift) || bad(gate.min_consistent) || gate.min_consistent > 1) {
    throw std::invalid_argument("odometry gate: base and drift must be >= 0, min_consistent in [0, 1]");
  }
  // travelled[k]: path length of the odometry from image 0 to image k.
  std::vector<double> travelled(odometry.size(), 0.0);
  for (std::size_t k = 1; k < odometry.size(); ++k) {
    travelled[k] = travelled[k - 1] + std::hypot(odometry[k].x - odometry[k - 1].x, odometry[k].y - odometry[k - 1].y);
  }
  std::vector<bool> out;
  out.reserve(alignments.size());
  for (const auto& alignment : alignments) {
    std::size_t consistent = 0;
    for (const auto& [i, j] : alignment.pairs) {
      if (i >= odometry.size() || j >= odometry.size()) {
        throw std::invalid_argument("alignment pair (" + std::to_string(i) + ", " + std::to_string(j) +
                                    ") is past the odometry's " + std::to_string(odometry.size()) + " poses");
      }
      const double apart = std::hypot(odometry[i].x - odometry[j].x, odometry[i].y - odometry[j].y);
      consistent += apart <= gate.base + gate.drift * std::abs(travelled[i] - travelled[j]);
    }
    out.push_back(!alignment.pairs.empty() &&
                  static_cast<double>(consistent) >= gate.min_consistent * static_cast<double>(alignment.pairs.size()));
  }
  return out;
}

}  // namespace seqtopo::mapping
