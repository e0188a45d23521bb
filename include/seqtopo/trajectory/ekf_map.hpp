#pragma once
// The mapping paper's metric picture (Section IV-D): an EKF whose prediction is odometry only and whose
// landmarks are the places of the topological map. The image similarity gives no bearing or range, so a
// place is a 2-D point and "observing" it means the robot is standing on it: h(x) = robot xy - place xy,
// measured as 0 with a symmetric 2-D Gaussian error. Data association is the map's labels.
#include <array>
#include <map>
#include <vector>

#include "seqtopo/core/pose2.hpp"

namespace seqtopo::trajectory {

struct EkfConfig {
  // Odometry noise of one step grows with the distance d travelled in it [m]:
  // sigma_xy = max(min_sigma_xy, odometry_sigma_xy_per_m * d) on each of the step's x and y [m],
  // sigma_theta = max(min_sigma_theta, odometry_sigma_theta_per_m * d) [rad].
  double odometry_sigma_xy_per_m = 0.05;     // [m/m]
  double odometry_sigma_theta_per_m = 0.02;  // [rad/m]
  double min_sigma_xy = 0.01;                // [m]
  double min_sigma_theta = 0.005;            // [rad]
  double observation_sigma = 0.5;            // [m] on each axis of the robot-on-place observation
};

struct EkfResult {
  // Filtered robot pose after image i (only observations up to i; the first traversal stays odometry).
  std::vector<Pose2> robot;
  // Final position of each place [m, m], all observations included. Negative labels have none.
  std::map<int, std::array<double, 2>> landmarks;
  // Where image i was taken, as drawn in the paper's figures: the final position of its place (so a
  // loop closed late also corrects the first traversal), with the filtered heading. Images with a
  // negative label keep their filtered robot pose.
  std::vector<Pose2> images;
};

// odometry[i]: cumulative odometry pose of image i; labels[i]: place label of image i (negative = none).
// A label seen for the first time initialises its landmark at the robot position; later images with that
// label observe it. The filter starts at odometry[0] with zero uncertainty (it fixes the map frame).
// Cost: a dense covariance over all P places, (3 + 2P)^2 doubles, and O(P^2) per revisiting image (about
// 1 s for 500 places, 10 s for 1000 on one core); pose_graph() scales to far larger maps.
// Throws std::invalid_argument when the sizes differ or a setting is not positive / finite.
EkfResult ekf_map(const std::vector<Pose2>& odometry, const std::vector<int>& labels, const EkfConfig& config = {});

}  // namespace seqtopo::trajectory
