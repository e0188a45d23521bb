#pragma once
// A pose with the time it was measured: the vocabulary of timestamped odometry (bags, TUM files, CSV with a
// timestamp column) before it is matched to the images.
#include "seqtopo/core/pose2.hpp"

namespace seqtopo {

struct TimedPose {
  double time = 0;  // [s], any epoch (the images' times must use the same one)
  Pose2 pose;       // T_world_robot [m, m, rad]
  friend bool operator==(const TimedPose&, const TimedPose&) = default;
};

}  // namespace seqtopo
