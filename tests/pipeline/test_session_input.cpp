// A session's odometry matched to its frames (session_input.hpp): image times from times.txt or numeric file
// names, per-frame and timestamped pose files, --every-metres, and the errors before any work.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/input_error_text.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/pipeline/session_input.hpp"
#include "seqtopo/plot/png.hpp"

namespace seqtopo::pipeline {
namespace {

namespace fs = std::filesystem;
using test_support::TempDir;

SessionSource make(const fs::path& input, const fs::path& odometry = {}, const fs::path& times = {}) {
  SessionSource s;
  s.input = SequenceInput(input);
  s.odometry = odometry;
  s.times = times;
  return s;
}

using test_support::error_of;

TEST(PrepareSession, NumericNamesInNanosecondsAndTimestampedCsv) {
  TempDir dir;
  const fs::path images = dir.path / "cam0";
  fs::create_directory(images);
  // EuRoC-style names: nanoseconds since the epoch.
  for (const char* name : {"1403636579763555584.png", "1403636580263555584.png", "1403636580763555584.png"}) {
    plot::write_png(images / name, RgbImage(4, 4, 50));
  }
  const auto csv =
      dir.write("odo.csv", "timestamp,x,y,yaw\n1403636579.5,0,0,0\n1403636580.5,2,0,0\n1403636581.5,2,4,0\n");
  SessionSource source = make(images, csv);
  const PreparedSession s = prepare_session(source);
  ASSERT_EQ(s.odometry.size(), 3U);
  EXPECT_NEAR(s.odometry[0].x, 2 * 0.263555584, 1e-6);
  EXPECT_NEAR(s.odometry[1].x, 2 * 0.763555584, 1e-6);
  EXPECT_NEAR(s.odometry[2].x, 2.0, 1e-9);
  EXPECT_NEAR(s.odometry[2].y, 4 * 0.263555584, 1e-6);
  EXPECT_EQ(s.frames, 3U);
  ASSERT_EQ(s.notes.size(), 1U);
  EXPECT_NE(s.notes[0].find("3 poses matched by time to 3 images"), std::string::npos) << s.notes[0];
}

TEST(PrepareSession, TimesTxtInTheFolderAndEveryMetres) {
  TempDir dir;
  for (int k = 0; k < 6; ++k) plot::write_png(dir.path / (std::to_string(k) + ".png"), RgbImage(4, 4, 30 * k));
  dir.write("times.txt", "0\n1\n2\n3\n4\n5\n");
  // TUM: moving 0.3 m per second along x.
  std::string tum;
  for (int k = 0; k <= 5; ++k) tum += std::to_string(k) + " " + std::to_string(0.3 * k) + " 0 0 0 0 0 1\n";
  const auto path = dir.write("poses.tum", tum);
  SessionSource source = make(dir.path, path);
  source.every_metres = 0.5;
  const PreparedSession s = prepare_session(source);
  // Path length 0, 0.3, 0.6, 0.9, 1.2, 1.5: marks 0.5, 1.0, 1.5 are reached at frames 2, 4, 5.
  EXPECT_EQ(s.input.frames, (std::vector<std::size_t>{0, 2, 4, 5}));
  ASSERT_EQ(s.odometry.size(), 4U);
  EXPECT_NEAR(s.odometry[1].x, 0.6, 1e-12);
  EXPECT_EQ(s.frames, 4U);
}

// The frames' times are kept for finding session breaks (timeline/session_breaks.hpp), odometry or not: from
// names that are times, a times.txt, --times (thinned by --every alike); none from names that are not times, nor
// with --every-metres.
TEST(PrepareSession, KeepsTheFramesTimesWhereTheRecordingHasThem) {
  TempDir dir;
  const fs::path numbered = dir.path / "numbered", named = dir.path / "named";
  fs::create_directories(numbered);
  fs::create_directories(named);
  for (int k : {10, 11, 12, 500}) plot::write_png(numbered / (std::to_string(k) + ".png"), RgbImage(4, 4, 9));
  for (const char* name : {"a.png", "b.png", "c.png"}) plot::write_png(named / name, RgbImage(4, 4, 9));
  EXPECT_EQ(prepare_session(make(numbered)).times, (std::vector<double>{10, 11, 12, 500}));
  SessionSource every = make(numbered);
  every.input.every = 2;
  EXPECT_EQ(prepare_session(every).times, (std::vector<double>{10, 12}));
  EXPECT_TRUE(prepare_session(make(named)).times.empty());
  const auto times = dir.write("times.txt", "0.5\n1.5\n9\n");
  EXPECT_EQ(prepare_session(make(named, {}, times)).times, (std::vector<double>{0.5, 1.5, 9}));
  // A times file the user gave must fit, odometry or not.
  const auto short_times = dir.write("short.txt", "0.5\n1.5\n");
  EXPECT_EQ(error_of([&] { prepare_session(make(named, {}, short_times)); }),
            short_times.string() + ": 2 image times for 3 images");
}

TEST(PrepareSession, ErrorsBeforeAnyWork) {
  TempDir dir;
  for (const char* name : {"a.png", "b.png"}) plot::write_png(dir.path / name, RgbImage(4, 4, 9));
  const auto timed = dir.write("odo.csv", "timestamp,x,y,yaw\n1,0,0,0\n2,1,0,0\n");
  EXPECT_NE(error_of([&] {
              prepare_session(make(dir.path, timed));
            }).find(timed.string() + ": holds timestamped poses, but the images have no times"),
            std::string::npos);
  const auto index = dir.write("index.csv", "index,x,y,theta\n0,0,0,0\n1,1,0,0\n2,2,0,0\n");
  EXPECT_EQ(error_of([&] { prepare_session(make(dir.path, index)); }),
            index.string() + ": has 3 poses, the sequence has 2 images");
  SessionSource no_odometry = make(dir.path);
  no_odometry.every_metres = 1.0;
  EXPECT_NE(error_of([&] { prepare_session(no_odometry); }).find("--every-metres: needs odometry"), std::string::npos);
  const auto times = dir.write("times3.txt", "1\n2\n3\n");
  SessionSource wrong_times = make(dir.path, timed, times);
  EXPECT_EQ(error_of([&] { prepare_session(wrong_times); }), times.string() + ": 3 image times for 2 images");
  SessionSource topic = make(dir.path);
  topic.odometry_topic = "/odom";
  EXPECT_NE(error_of([&] { prepare_session(topic); }).find("--odometry-topic: needs a bag input"), std::string::npos);
}

TEST(InputKind, RosTwoBagFolder) {
  TempDir dir;
  dir.touch("metadata.yaml");
  dir.touch("run_0.db3");
  EXPECT_EQ(resolve_input_kind(SequenceInput(dir.path)), InputKind::bag);
  EXPECT_EQ(resolve_input_kind(SequenceInput(dir.path / "run_0.db3")), InputKind::bag);
  fs::remove(dir.path / "run_0.db3");
  EXPECT_EQ(resolve_input_kind(SequenceInput(dir.path)), InputKind::images);
  EXPECT_EQ(parse_input_kind("bag"), InputKind::bag);
}

}  // namespace
}  // namespace seqtopo::pipeline
