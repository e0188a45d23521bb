#include "seqtopo/trajectory/trajectory_error.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace seqtopo::trajectory {

RigidAlignment align_trajectory(const std::vector<Pose2>& estimate, const std::vector<Pose2>& truth) {
  if (estimate.size() != truth.size()) {
    throw std::invalid_argument("trajectory error: " + std::to_string(estimate.size()) + " estimated poses but " +
                                std::to_string(truth.size()) + " true poses");
  }
  if (estimate.empty()) throw std::invalid_argument("trajectory error: empty trajectories");
  const double n = static_cast<double>(estimate.size());
  double ex = 0, ey = 0, tx = 0, ty = 0;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    ex += estimate[i].x;
    ey += estimate[i].y;
    tx += truth[i].x;
    ty += truth[i].y;
  }
  ex /= n, ey /= n, tx /= n, ty /= n;
  // With centred points e and t, the rotation maximising sum t . R e has angle atan2(sum e x t, sum e . t).
  double dot = 0, cross = 0;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    const double ax = estimate[i].x - ex, ay = estimate[i].y - ey;
    const double bx = truth[i].x - tx, by = truth[i].y - ty;
    dot += ax * bx + ay * by;
    cross += ax * by - ay * bx;
  }
  const double angle = std::atan2(cross, dot);
  const double c = std::cos(angle), s = std::sin(angle);
  RigidAlignment result;
  result.transform = {tx - (c * ex - s * ey), ty - (s * ex + c * ey), angle};
  double sum = 0;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    const double ax = estimate[i].x - ex, ay = estimate[i].y - ey;
    const double dx = c * ax - s * ay - (truth[i].x - tx);
    const double dy = s * ax + c * ay - (truth[i].y - ty);
    sum += dx * dx + dy * dy;
  }
  result.rmse = std::sqrt(sum / n);
  return result;
}

double absolute_trajectory_error(const std::vector<Pose2>& estimate, const std::vector<Pose2>& truth) {
  return align_trajectory(estimate, truth).rmse;
}

}  // namespace seqtopo::trajectory
