#pragma once
// Timestamped odometry matched to image times, and the frames kept one per D metres travelled. Pure
// functions over plain data: the readers (formats/pose_files.hpp, recording/) produce the inputs.
//
//   auto poses = timeline::interpolate_poses(odometry, image_times);   // one Pose2 per image
//   auto keep  = timeline::select_every_metres(poses.poses, 0.5);      // the paper's outdoor spacing
#include <cstddef>
#include <span>
#include <vector>

#include "seqtopo/core/pose2.hpp"
#include "seqtopo/core/timed_pose.hpp"

namespace seqtopo::timeline {

struct InterpolationConfig {
  // An image up to this long before the first pose or after the last one gets that end pose (a camera
  // that starts a few frames before the odometry); farther out is an error. [s]
  double max_extrapolation = 0.5;
};

struct InterpolatedPoses {
  std::vector<Pose2> poses;     // one per image time
  std::size_t held_at_end = 0;  // images given an end pose (within max_extrapolation of the pose range)
};

// The pose at each of `times`: linear in x and y, along the shorter arc in theta, between the two poses
// around it; a time equal to a pose's time gets that pose exactly. `poses` must be sorted by time with no two
// at the same time, all finite. Throws std::invalid_argument with a message a user can act on when `poses`
// is empty or unsorted, when a time is not finite, when the two time ranges do not overlap at all
// ("images 10.0 .. 12.0 s, poses 50.0 .. 60.0 s"), or when some images lie farther than max_extrapolation
// outside the poses' range.
InterpolatedPoses interpolate_poses(std::span<const TimedPose> poses, std::span<const double> times,
                                    const InterpolationConfig& config = {});

// Frames kept one per `metres` of odometry (the mapping paper records one image every 0.25 m indoors and
// 0.5 m outdoors): frame 0, then the first frame whose path length travelled from frame 0 reaches each of
// metres, 2 metres, 3 metres, ... (one frame when a step passes several marks; no frame while standing still).
// Increasing indices into `poses`. Throws std::invalid_argument when metres is not > 0 or a pose is not finite.
std::vector<std::size_t> select_every_metres(std::span<const Pose2> poses, double metres);

// Strictly increasing times: throws std::invalid_argument naming the first index out of order.
void check_increasing(std::span<const double> times);

}  // namespace seqtopo::timeline
