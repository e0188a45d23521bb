#pragma once
// The odometry and pose files of robotics datasets (docs/recordings.md), and image times:
//  * CSV with a header `timestamp,x,y,yaw` (also `timestamp,x,y,theta` or `timestamp,x,y`; `time` or `t`
//    for `timestamp`) [s, m, m, rad]: timestamped poses;
//  * TUM RGB-D (`timestamp tx ty tz qx qy qz qw` per line, `#` comments) [s, m, unit quaternion]:
//    timestamped poses, the planar pose is (tx, ty) and the yaw about z;
//  * KITTI odometry poses (12 numbers per line: the 3 x 4 matrix [R | t] row by row, camera frame x right,
//    y down, z forward): one pose per frame, no time; the planar pose is (tz, -tx) and the heading about the
//    camera's y axis;
//  * seqtopo's own `index,x,y,theta` / `index,dx,dy,dtheta` CSV (odometry_csv.hpp): one pose per frame;
//  * times.txt: one time per line [s] (KITTI's times.txt), the time of each image.
// Every reader throws InputError naming file:line and the problem (not a number, not finite, a wrong field
// count, a quaternion that is not a rotation, times out of order), or the file when it cannot be opened or
// holds nothing.
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "seqtopo/core/pose2.hpp"
#include "seqtopo/core/timed_pose.hpp"

namespace seqtopo::formats {

enum class PoseFileKind { index_csv, timestamped_csv, tum, kitti };
std::string_view pose_file_kind_name(PoseFileKind kind);

struct PoseFile {
  PoseFileKind kind = PoseFileKind::index_csv;
  std::vector<Pose2> per_frame;  // index_csv, kitti: one pose per image
  std::vector<TimedPose> timed;  // timestamped_csv, tum: sorted by time (checked)
  bool timestamped() const { return kind == PoseFileKind::timestamped_csv || kind == PoseFileKind::tum; }
};

// The kind from the first line that is not blank nor a `#` comment: a CSV header starting with `index`
// or with `timestamp`/`time`/`t`; else whitespace-separated numbers, 8 per line (TUM) or 12 (KITTI).
PoseFile read_pose_file(const std::filesystem::path& path);

std::vector<TimedPose> read_timestamped_csv(const std::filesystem::path& path);
std::vector<TimedPose> read_tum(const std::filesystem::path& path);
std::vector<Pose2> read_kitti_poses(const std::filesystem::path& path);

// One time per line [s], increasing; blank lines and `#` comments skipped.
std::vector<double> read_times_txt(const std::filesystem::path& path);

// Planar poses written for other tools (a SLAM back end, evo): TUM lines `time x y 0 0 0 sin(theta/2) cos(theta/2)`
// (`times`: one per pose [s]), and KITTI lines, the 3 x 4 matrix [R | t] of the camera frame row by row, so that
// read_tum and read_kitti_poses give the poses back. 9 significant digits.
std::string tum_text(std::span<const Pose2> poses, std::span<const double> times);
std::string kitti_text(std::span<const Pose2> poses);

// The planar heading [rad] of a unit quaternion (yaw about z); nullopt when it is not (close to) unit length.
std::optional<double> yaw_of_quaternion(double qx, double qy, double qz, double qw);

}  // namespace seqtopo::formats
