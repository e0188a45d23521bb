// Poses matched to image times, and frames kept one per D metres.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "seqtopo/timeline/timed_poses.hpp"

namespace seqtopo::timeline {
namespace {

TEST(InterpolatePoses, ExactAtSamplesLinearBetween) {
  const std::vector<TimedPose> poses{{10.0, {0, 0, 0}}, {11.0, {1, 2, 0.5}}, {13.0, {3, 2, 0.5}}};
  const std::vector<double> times{10.0, 10.5, 11.0, 12.0, 13.0};
  const auto r = interpolate_poses(poses, times);
  ASSERT_EQ(r.poses.size(), 5U);
  EXPECT_EQ(r.poses[0], poses[0].pose);
  EXPECT_EQ(r.poses[2], poses[1].pose);  // bit for bit at a sample's time
  EXPECT_EQ(r.poses[4], poses[2].pose);
  EXPECT_DOUBLE_EQ(r.poses[1].x, 0.5);
  EXPECT_DOUBLE_EQ(r.poses[1].y, 1.0);
  EXPECT_DOUBLE_EQ(r.poses[1].theta, 0.25);
  EXPECT_DOUBLE_EQ(r.poses[3].x, 2.0);
  EXPECT_EQ(r.held_at_end, 0U);
}

TEST(InterpolatePoses, HeadingTakesTheShorterArc) {
  const double pi = std::numbers::pi;
  const std::vector<TimedPose> poses{{0.0, {0, 0, pi - 0.1}}, {1.0, {0, 0, -pi + 0.1}}};
  const auto r = interpolate_poses(poses, std::vector<double>{0.5});
  // Through pi, not through 0.
  EXPECT_NEAR(std::abs(r.poses[0].theta), pi, 1e-12);
}

TEST(InterpolatePoses, EndsHeldWithinTheToleranceOnly) {
  const std::vector<TimedPose> poses{{10.0, {1, 0, 0}}, {20.0, {2, 0, 0}}};
  const auto r = interpolate_poses(poses, std::vector<double>{9.8, 15.0, 20.3});
  EXPECT_EQ(r.held_at_end, 2U);
  EXPECT_EQ(r.poses[0], poses[0].pose);
  EXPECT_EQ(r.poses[2], poses[1].pose);
  try {
    interpolate_poses(poses, std::vector<double>{15.0, 21.0, 22.0});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("2 of 3 images"), std::string::npos) << e.what();
  }
}

TEST(InterpolatePoses, RangesThatDoNotOverlapAreAClearError) {
  const std::vector<TimedPose> poses{{50.0, {0, 0, 0}}, {60.0, {1, 0, 0}}};
  try {
    interpolate_poses(poses, std::vector<double>{10.0, 11.0, 12.0});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "the time ranges do not overlap: images 10.000 .. 12.000 s, poses 50.000 .. 60.000 s");
  }
}

TEST(InterpolatePoses, RejectsUnsortedAndNonFinite) {
  EXPECT_THROW(interpolate_poses(std::vector<TimedPose>{}, std::vector<double>{1.0}), std::invalid_argument);
  EXPECT_THROW(interpolate_poses(std::vector<TimedPose>{{2.0, {}}, {1.0, {}}}, std::vector<double>{1.5}),
               std::invalid_argument);
  EXPECT_THROW(interpolate_poses(std::vector<TimedPose>{{1.0, {}}, {2.0, {}}}, std::vector<double>{NAN}),
               std::invalid_argument);
  EXPECT_THROW(interpolate_poses(std::vector<TimedPose>{{1.0, {INFINITY, 0, 0}}}, std::vector<double>{1.0}),
               std::invalid_argument);
}

TEST(SelectEveryMetres, OneFramePerDistanceTravelled) {
  // 0.125 m per frame (exact in binary), then standing still for 5 frames, then 0.375 m per frame.
  std::vector<Pose2> poses;
  double x = 0;
  for (int k = 0; k < 10; ++k) poses.push_back({x += 0.125, 0, 0});
  for (int k = 0; k < 5; ++k) poses.push_back({x, 0, 0});
  for (int k = 0; k < 5; ++k) poses.push_back({x += 0.375, 0, 0});
  const auto kept = select_every_metres(poses, 0.5);
  // Frame 0, then the first frame at or past 0.5, 1.0, 1.5, ... m travelled; standing still (frames 10..14)
  // adds nothing; frame 17 (2.25 m) passes the 2.0 mark, frame 18 (2.625 m) the 2.5 one.
  EXPECT_EQ(kept, (std::vector<std::size_t>{0, 4, 8, 15, 17, 18, 19}));
  EXPECT_EQ(select_every_metres(poses, 100.0), (std::vector<std::size_t>{0}));
  EXPECT_EQ(select_every_metres(poses, 1e-9).size(), 15U);  // every frame that moved, and frame 0
  EXPECT_THROW(select_every_metres(poses, 0.0), std::invalid_argument);
  EXPECT_THROW(select_every_metres(poses, NAN), std::invalid_argument);
  EXPECT_TRUE(select_every_metres({}, 1.0).empty());
}

TEST(SelectEveryMetres, OneFramePerMarkPassed) {
  // A jump of 2.5 m passes the marks 0.5 .. 2.5 at once: one frame, the next mark at 3.0 m.
  std::vector<Pose2> poses{{0, 0, 0}, {2.5, 0, 0}, {2.9, 0, 0}, {3.0, 0, 0}};
  EXPECT_EQ(select_every_metres(poses, 0.5), (std::vector<std::size_t>{0, 1, 3}));
}

TEST(SelectEveryMetres, PathLengthNotStraightLine) {
  // A back-and-forth: 1 m out and 1 m back is 2 m travelled though the end is where it started.
  std::vector<Pose2> poses{{0, 0, 0}, {1, 0, 0}, {0, 0, 0}};
  EXPECT_EQ(select_every_metres(poses, 1.0), (std::vector<std::size_t>{0, 1, 2}));
}

}  // namespace
}  // namespace seqtopo::timeline
