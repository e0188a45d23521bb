#pragma once
// Odometry and ground-truth poses as CSV text. Only the header-only Pose2 is used, so io does not link the
// metric estimator.
#include <filesystem>
#include <vector>

#include "seqtopo/core/pose2.hpp"

namespace seqtopo::formats {

// Header `index,x,y,theta`: the cumulative odometry pose of each image [m, m, rad].
// Header `index,dx,dy,dtheta`: the motion since the previous row, in the robot frame of the previous pose
// [m, m, rad]; integrated from the origin, so row 0 is the first pose itself (usually 0,0,0).
// Rows must have indices 0..N-1 in order. Blank lines and spaces around fields are ignored.
// Throws InputError naming file:line on a bad header, a non-numeric or non-finite field, a wrong field
// count, an index out of order or increments whose integrated position is not finite (1e308 + 1e308), and
// naming the file when it cannot be opened or has no rows.
std::vector<Pose2> read_odometry_csv(const std::filesystem::path& path);

// Ground-truth poses: header `index,x,y` or `index,x,y,theta` [m, m, rad]; theta is 0 when absent.
// Same rules and errors as read_odometry_csv.
std::vector<Pose2> read_poses_csv(const std::filesystem::path& path);

}  // namespace seqtopo::formats
