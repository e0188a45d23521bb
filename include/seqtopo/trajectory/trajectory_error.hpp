#pragma once
// Absolute trajectory error: how far an estimated path is from the truth once the arbitrary choice of
// map frame is factored out.
#include <vector>

#include "seqtopo/core/pose2.hpp"

namespace seqtopo::trajectory {

// A rigid 2-D transform: p_truth ~= R(theta) * p_estimate + (x, y).
struct RigidAlignment {
  Pose2 transform;
  double rmse = 0;  // [m]
};

// Best rigid alignment (rotation + translation, no scale) of the estimate's positions onto the truth's,
// in closed form (least squares, 2-D Umeyama/Kabsch), and the RMSE of the positions after it. Headings
// are ignored. Throws std::invalid_argument when the sizes differ or the trajectories are empty.
RigidAlignment align_trajectory(const std::vector<Pose2>& estimate, const std::vector<Pose2>& truth);

// RMSE of positions after the best rigid 2-D alignment [m].
double absolute_trajectory_error(const std::vector<Pose2>& estimate, const std::vector<Pose2>& truth);

}  // namespace seqtopo::trajectory
