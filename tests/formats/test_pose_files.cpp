// Timestamped CSV, TUM, KITTI and times.txt readers: values, auto-detection, and one error naming file:line.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "common/input_error_text.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/formats/odometry_csv.hpp"
#include "seqtopo/formats/pose_files.hpp"

namespace seqtopo::formats {
namespace {

using test_support::TempDir;

using test_support::error_of;

TEST(PoseFiles, TimestampedCsv) {
  TempDir dir;
  const auto path = dir.write("odo.csv", "timestamp,x,y,yaw\n10.5,1,2,0.25\n\n11.0, 2, 3, -0.5\n");
  const PoseFile f = read_pose_file(path);
  EXPECT_EQ(f.kind, PoseFileKind::timestamped_csv);
  ASSERT_EQ(f.timed.size(), 2U);
  EXPECT_EQ(f.timed[0], (TimedPose{10.5, {1, 2, 0.25}}));
  EXPECT_EQ(f.timed[1], (TimedPose{11.0, {2, 3, -0.5}}));
  const auto unsorted = dir.write("bad.csv", "timestamp,x,y,yaw\n2,0,0,0\n1,0,0,0\n");
  EXPECT_NE(error_of([&] { read_pose_file(unsorted); }).find(unsorted.string() + ":3: timestamp"), std::string::npos);
  const auto nan = dir.write("nan.csv", "timestamp,x,y,yaw\n1,nan,0,0\n");
  EXPECT_EQ(error_of([&] { read_pose_file(nan); }), nan.string() + ":2: field 'x' is not finite");
}

// Spreadsheets save CSV with a UTF-8 byte-order mark before the header: the same poses as without it.
TEST(PoseFiles, AByteOrderMarkBeforeTheHeaderIsSkipped) {
  TempDir dir;
  const std::string text = "index,x,y,theta\n0,0,0,0\n1,1.5,0,0.25\n";
  const auto plain = dir.write("plain.csv", text), marked = dir.write("marked.csv", "\xEF\xBB\xBF" + text);
  const auto expected = read_odometry_csv(plain);
  ASSERT_EQ(expected.size(), 2U);
  EXPECT_EQ(read_odometry_csv(marked), expected);
  EXPECT_EQ(read_poses_csv(marked), read_poses_csv(plain));
  const auto timed = dir.write("timed.csv", "\xEF\xBB\xBFtimestamp,x,y,yaw\n10.5,1,2,0.25\n11,2,3,0\n");
  EXPECT_EQ(read_pose_file(timed).kind, PoseFileKind::timestamped_csv);
}

TEST(PoseFiles, TumWithCommentsAndYaw) {
  TempDir dir;
  const double yaw = 0.7;
  const auto path =
      dir.write("tum.txt", "# timestamp tx ty tz qx qy qz qw\n1305031102.175304 1.5 -2 0.3 0 0 " +
                               std::to_string(std::sin(yaw / 2)) + " " + std::to_string(std::cos(yaw / 2)) + "\n");
  const PoseFile f = read_pose_file(path);
  EXPECT_EQ(f.kind, PoseFileKind::tum);
  ASSERT_EQ(f.timed.size(), 1U);
  EXPECT_DOUBLE_EQ(f.timed[0].time, 1305031102.175304);
  EXPECT_DOUBLE_EQ(f.timed[0].pose.x, 1.5);
  EXPECT_DOUBLE_EQ(f.timed[0].pose.y, -2.0);
  EXPECT_NEAR(f.timed[0].pose.theta, yaw, 1e-6);
  const auto bad = dir.write("bad.txt", "1 0 0 0 0 0 0 2\n");
  EXPECT_EQ(error_of([&] { read_pose_file(bad); }),
            bad.string() + ":1: the quaternion qx qy qz qw is not of unit length");
  const auto short_line = dir.write("short.txt", "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n");
  EXPECT_NE(error_of([&] { read_pose_file(short_line); }).find(":2: a TUM line has 8 numbers"), std::string::npos);
}

TEST(PoseFiles, KittiCameraFrameToPlane) {
  TempDir dir;
  // Camera turned by a about its y axis (down): forward z becomes (sin a, 0, cos a); position (tx, ty, tz).
  const double a = 0.3;
  const double c = std::cos(a), s = std::sin(a);
  const std::string line = std::to_string(c) + " 0 " + std::to_string(s) + " 4 0 1 0 0 " + std::to_string(-s) + " 0 " +
                           std::to_string(c) + " 7\n";
  const auto path = dir.write("poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n" + line);
  const PoseFile f = read_pose_file(path);
  EXPECT_EQ(f.kind, PoseFileKind::kitti);
  ASSERT_EQ(f.per_frame.size(), 2U);
  EXPECT_EQ(f.per_frame[0], (Pose2{0, 0, 0}));
  EXPECT_DOUBLE_EQ(f.per_frame[1].x, 7.0);      // forward tz
  EXPECT_DOUBLE_EQ(f.per_frame[1].y, -4.0);     // left = -tx
  EXPECT_NEAR(f.per_frame[1].theta, -a, 1e-6);  // turning towards +x (right) is a negative yaw
}

TEST(PoseFiles, TimesTxtAndDetectionErrors) {
  TempDir dir;
  const auto times = dir.write("times.txt", "0.000000e+00\n1.036224e-01\n2.072449e-01\n");
  EXPECT_EQ(read_times_txt(times), (std::vector<double>{0.0, 1.036224e-01, 2.072449e-01}));
  const auto back = dir.write("back.txt", "1\n0.5\n");
  EXPECT_NE(error_of([&] { read_times_txt(back); }).find(back.string() + ":2:"), std::string::npos);
  const auto odd = dir.write("odd.txt", "1 2 3\n");
  EXPECT_NE(error_of([&] { read_pose_file(odd); }).find(odd.string() + ":1: not a pose file"), std::string::npos);
  const auto header = dir.write("header.csv", "stamp,x,y\n");
  EXPECT_NE(error_of([&] { read_pose_file(header); }).find(header.string() + ":1:"), std::string::npos);
  EXPECT_EQ(read_pose_file(dir.write("index.csv", "index,x,y,theta\n0,1,2,0\n")).kind, PoseFileKind::index_csv);
}

// Issue #18 (b): finite increments whose sum is not finite are refused, naming the file and the line.
// The corrected trajectory is written for other tools as TUM and KITTI: read back, the same planar poses.
TEST(PoseFiles, TumAndKittiWrittenReadBackAsTheSamePoses) {
  TempDir dir;
  const std::vector<Pose2> poses{{0, 0, 0}, {1.5, -2.25, 0.5}, {-3, 4, -2.5}, {10, 0.125, 3.0}};
  const std::vector<double> times{0, 1, 2, 3};
  const auto tum = read_tum(dir.write("t.txt", tum_text(poses, times)));
  const auto kitti = read_kitti_poses(dir.write("k.txt", kitti_text(poses)));
  ASSERT_EQ(tum.size(), poses.size());
  ASSERT_EQ(kitti.size(), poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    EXPECT_EQ(tum[k].time, times[k]);
    for (const Pose2& p : {tum[k].pose, kitti[k]}) {
      EXPECT_NEAR(p.x, poses[k].x, 1e-8) << k;
      EXPECT_NEAR(p.y, poses[k].y, 1e-8) << k;
      EXPECT_NEAR(std::remainder(p.theta - poses[k].theta, 2 * std::numbers::pi), 0.0, 1e-8) << k;
    }
  }
  EXPECT_EQ(read_pose_file(dir.write("auto_k.txt", kitti_text(poses))).kind, PoseFileKind::kitti);
  EXPECT_EQ(read_pose_file(dir.write("auto_t.txt", tum_text(poses, times))).kind, PoseFileKind::tum);
}

TEST(OdometryCsv, NonFiniteIntegratedPositionIsRefused) {
  TempDir dir;
  const auto path = dir.write("odo.csv", "index,dx,dy,dtheta\n0,1e308,0,0\n1,1e308,0,0\n");
  EXPECT_EQ(error_of([&] { read_odometry_csv(path); }),
            path.string() + ":3: the integrated position is not finite (the increments overflow)");
  const auto fine = dir.write("fine.csv", "index,dx,dy,dtheta\n0,1e307,0,0\n1,1e307,0,0\n");
  EXPECT_DOUBLE_EQ(read_odometry_csv(fine).back().x, 2e307);
}

}  // namespace
}  // namespace seqtopo::formats
