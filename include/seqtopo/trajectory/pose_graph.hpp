#pragma once
// A better metric picture than the paper's EKF: a 2-D pose graph over all images, solved with Ceres.
// Odometry edges join consecutive images; every retained image pair of the topological map adds an edge
// that pulls the two positions together. The pair says "same place" but gives no bearing or distance, so
// that edge is position-only, and a robust loss keeps a few wrong pairs from bending the whole map.
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "seqtopo/core/pose2.hpp"

namespace seqtopo::trajectory {

struct PoseGraphConfig {
  // Odometry edge noise grows with the step length d [m]: sigma_xy = max(min_sigma_xy,
  // odometry_sigma_xy * d) [m] on each axis, sigma_theta = max(min_sigma_theta, odometry_sigma_theta * d)
  // [rad] (the same model as EkfConfig, so the two pictures are comparable).
  double odometry_sigma_xy = 0.05;     // [m/m]
  double odometry_sigma_theta = 0.02;  // [rad/m]
  double loop_sigma_xy = 0.5;          // [m] on each axis of the "same place" edge
  std::string loss = "cauchy";         // on loop edges: "cauchy", "huber" or "none"
  double loss_scale = 1.0;             // where the robust loss starts to flatten [sigmas]
  int max_iterations = 100;
  unsigned threads = 1;            // > 1 is faster on big maps; 1 gives bit-identical runs
  double min_sigma_xy = 0.01;      // [m]
  double min_sigma_theta = 0.005;  // [rad]
};

// loop_pairs: image pairs (i, j) judged the same place. Returns one optimised pose per image; the first
// pose stays at odometry[0] (it fixes the map frame). With no pairs the result is the odometry.
// Throws std::invalid_argument on a pair index out of range, an unknown loss or a non-positive setting.
std::vector<Pose2> pose_graph(const std::vector<Pose2>& odometry,
                              const std::vector<std::pair<std::size_t, std::size_t>>& loop_pairs,
                              const PoseGraphConfig& config = {});

}  // namespace seqtopo::trajectory
