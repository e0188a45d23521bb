// The bundled corridor packed into bags (ROS 1 .bag, ROS 2 .db3 and .mcap; images as sensor_msgs/Image and as
// CompressedImage, with a nav_msgs/Odometry topic) maps exactly as the image folder does with the same
// odometry: byte-identical map.json. And bad bags get one error line naming the file and the problem.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "bag_writer.hpp"
#include "common/cli_run.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/core/pose2.hpp"
#include "seqtopo/image/image_io.hpp"
#include "seqtopo/pipeline/sequence_input.hpp"

namespace seqtopo {
namespace {

namespace fs = std::filesystem;
using test_support::BagKind;
using test_support::read_file;
using test_support::Recipe;
using test_support::run_cli;
using test_support::TempDir;

const fs::path kCorridor = fs::path(SEQTOPO_SOURCE_DIR) / "data" / "rtabmap-corridor";

// The corridor is one loop walked twice (images 41..84 revisit 1..44, 1-based): 40 images per lap, on a
// circle of 20 m, starting at the origin heading along x.
Pose2 loop_pose(double k) {
  const double a = 2 * std::numbers::pi * k / 40.0, r = 20.0 / (2 * std::numbers::pi);
  return {r * std::sin(a), r * (1 - std::cos(a)), wrap_angle(a)};
}

std::string format_double(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

class CorridorBags : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    files_ = pipeline::list_images(kCorridor);
    // The folder's run with the same odometry, index,x,y,theta, is the reference.
    std::ofstream csv(dir_->path / "odometry.csv");
    csv << "index,x,y,theta\n";
    for (std::size_t k = 0; k < files_.size(); ++k) {
      const Pose2 p = loop_pose(static_cast<double>(k));
      csv << k << "," << format_double(p.x) << "," << format_double(p.y) << "," << format_double(p.theta) << "\n";
    }
    csv.close();
    const auto r = run_cli("map " + kCorridor.string() + " --odometry " + (dir_->path / "odometry.csv").string() +
                           " --out " + (dir_->path / "folder").string());
    ASSERT_EQ(r.status, 0) << r.err;
    reference_ = read_file(dir_->path / "folder" / "map.json");
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }

  // The corridor as a recipe: image k at 1000 + 0.5 k s, raw (PPM pixels decoded by seqtopo's own reader,
  // as the folder run sees them; encoding rgb8 or bgr8) or compressed (the JPEG files' own bytes), and the
  // odometry at the images' times.
  static Recipe corridor(bool compressed, const std::string& encoding = "rgb8") {
    Recipe r;
    for (std::size_t k = 0; k < files_.size(); ++k) {
      const double t = 1000.0 + 0.5 * static_cast<double>(k);
      if (compressed) {
        r.compressed("/camera/image/compressed", t, files_[k], "jpeg");
      } else {
        const fs::path ppm = dir_->path / (encoding + "-" + std::to_string(k) + ".ppm");
        if (!fs::exists(ppm)) {
          RgbImage image = image::load_image(files_[k]);
          if (encoding == "bgr8") {
            for (std::size_t p = 0; p < image.pixels.size(); p += 3) std::swap(image.pixels[p], image.pixels[p + 2]);
          }
          test_support::write_ppm(ppm, image);
        }
        r.raw_image("/camera/image_raw", t, ppm, RgbImage(512, 384), encoding);
      }
      const Pose2 p = loop_pose(static_cast<double>(k));
      r.pose("/odom", "nav_msgs/msg/Odometry", t, p.x, p.y, p.theta);
    }
    return r;
  }

  static void expect_same_map(BagKind kind, bool compressed, const std::string& encoding = "rgb8") {
    const std::string name = std::string(test_support::bag_kind_name(kind)) + (compressed ? "-compressed" : "-raw");
    const fs::path bag = dir_->path / (name + test_support::bag_extension(kind));
    test_support::write_bag(corridor(compressed, encoding), kind, bag);
    const fs::path out = dir_->path / name;
    const auto r = run_cli("map " + bag.string() + " --out " + out.string());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("odometry from " + bag.string() + ":/odom: 84 poses matched by time to 84 images"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(read_file(out / "map.json"), reference_) << name << ": map.json differs from the folder's";
    fs::remove(bag);
  }

  static TempDir* dir_;
  static std::vector<fs::path> files_;
  static std::string reference_;
};
TempDir* CorridorBags::dir_ = nullptr;
std::vector<fs::path> CorridorBags::files_;
std::string CorridorBags::reference_;

TEST_F(CorridorBags, Ros1ImageMapsAsTheFolder) { expect_same_map(BagKind::ros1, false); }
TEST_F(CorridorBags, Ros1CompressedImageMapsAsTheFolder) { expect_same_map(BagKind::ros1, true); }
TEST_F(CorridorBags, Db3ImageBgr8MapsAsTheFolder) { expect_same_map(BagKind::db3, false, "bgr8"); }
TEST_F(CorridorBags, Db3CompressedImageMapsAsTheFolder) { expect_same_map(BagKind::db3, true); }
TEST_F(CorridorBags, McapZstdImageMapsAsTheFolder) { expect_same_map(BagKind::mcap_zstd, false); }
TEST_F(CorridorBags, McapLz4CompressedImageMapsAsTheFolder) { expect_same_map(BagKind::mcap_lz4, true); }

// The odometry matters: the same bag without its odometry topic maps as the folder without odometry, and
// the reference with odometry is not that map (the odometry gate and the trajectory see it).
TEST_F(CorridorBags, WithoutOdometryTopicMapsAsTheFolderWithoutOdometry) {
  const fs::path bag = dir_->path / "plain.mcap";
  test_support::write_bag(corridor(true), BagKind::mcap_zstd, bag);
  const auto folder = run_cli("map " + kCorridor.string() + " --out " + (dir_->path / "plain-folder").string());
  ASSERT_EQ(folder.status, 0) << folder.err;
  const auto r = run_cli("map " + bag.string() + " --odometry-topic none --out " + (dir_->path / "plain").string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(read_file(dir_->path / "plain" / "map.json"), read_file(dir_->path / "plain-folder" / "map.json"));
  EXPECT_FALSE(fs::exists(dir_->path / "plain" / "metric_map.png"));
  EXPECT_TRUE(fs::exists(dir_->path / "folder" / "metric_map.png"));
  // The same command on the folder's images with an odometry that contradicts the loop drops its alignments.
  std::ofstream line(dir_->path / "straight.csv");
  line << "index,x,y,theta\n";
  for (int k = 0; k < 84; ++k) line << k << "," << 0.5 * k << ",0,0\n";
  line.close();
  const auto straight = run_cli("map " + bag.string() + " --odometry " + (dir_->path / "straight.csv").string() +
                                " --out " + (dir_->path / "straight").string());
  ASSERT_EQ(straight.status, 0) << straight.err;
  EXPECT_NE(read_file(dir_->path / "straight" / "map.json"), read_file(dir_->path / "plain" / "map.json"));
}

// ---- bad bags: one error line naming the file and the problem ---------------------------------------------

void expect_one_error_line(const test_support::CommandResult& r, const std::string& starts,
                           const std::string& contains) {
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.status, -1) << "must exit, not crash";
  std::string err = r.err;
  if (!err.empty() && err.back() == '\n') err.pop_back();
  EXPECT_EQ(err.find('\n'), std::string::npos) << "one line expected:\n" << r.err;
  EXPECT_EQ(err.rfind(starts, 0), 0U) << err;
  EXPECT_NE(err.find(contains), std::string::npos) << err;
}

class BadBags : public ::testing::Test {
 protected:
  TempDir dir_;
  Recipe small(const std::string& encoding = "rgb8") {
    Recipe r;
    RgbImage image(8, 6, 77);
    const fs::path ppm = dir_.path / "small.ppm";
    test_support::write_ppm(ppm, image);
    for (int k = 0; k < 4; ++k) {
      if (encoding == "rgb8") {
        r.raw_image("/cam", k + 1, ppm, image);
      } else {
        r.raw_bytes("/cam", k + 1, 8, 6, encoding, 16, std::vector<std::uint8_t>(96, 3));
      }
      r.pose("/odom", "nav_msgs/msg/Odometry", k + 1, k, 0, 0);
    }
    return r;
  }
  std::string out() const { return " --out " + (dir_.path / "out").string(); }
};

TEST_F(BadBags, TruncatedBagOfEachFormat) {
  for (const BagKind kind : test_support::all_bag_kinds()) {
    const fs::path bag =
        dir_.path / (std::string("cut-") + test_support::bag_kind_name(kind) + test_support::bag_extension(kind));
    test_support::write_bag(small(), kind, bag);
    fs::resize_file(bag, fs::file_size(bag) / 2);
    expect_one_error_line(run_cli("map " + bag.string() + out()), "seqtopo: error: " + bag.string() + ": ", "");
    EXPECT_FALSE(fs::exists(dir_.path / "out")) << "no partial output";
  }
}

TEST_F(BadBags, WrongTopicListsTheCandidates) {
  const fs::path bag = dir_.path / "small.db3";
  test_support::write_bag(small(), BagKind::db3, bag);
  expect_one_error_line(run_cli("map " + bag.string() + " --image-topic /camera" + out()),
                        "seqtopo: error: " + bag.string() + ": ",
                        "no topic /camera in the bag; its image topics: /cam (sensor_msgs/msg/Image)");
  expect_one_error_line(run_cli("map " + bag.string() + " --odometry-topic /cam" + out()),
                        "seqtopo: error: " + bag.string() + ": ", "holds sensor_msgs/msg/Image, not nav_msgs/Odometry");
}

TEST_F(BadBags, UnknownEncoding) {
  const fs::path bag = dir_.path / "yuv.bag";
  test_support::write_bag(small("yuv422"), BagKind::ros1, bag);
  expect_one_error_line(run_cli("map " + bag.string() + out()), "seqtopo: error: " + bag.string() + ": ",
                        "topic /cam, image 0: image encoding 'yuv422' is not supported");
}

TEST_F(BadBags, CorruptCompressedChunk) {
  const fs::path bag = dir_.path / "small.mcap";
  test_support::write_bag(small(), BagKind::mcap_zstd, bag);
  test_support::corrupt_first_chunk(bag);
  expect_one_error_line(run_cli("map " + bag.string() + out()), "seqtopo: error: " + bag.string() + ": ", "chunk");
}

TEST_F(BadBags, OdometryOutsideTheImagesTime) {
  Recipe r = small();
  for (auto& m : r.topics[1]["messages"]) m["sec"] = m["sec"].get<int>() + 500;
  const fs::path bag = dir_.path / "late.mcap";
  test_support::write_bag(r, BagKind::mcap_lz4, bag);
  expect_one_error_line(run_cli("map " + bag.string() + out()), "seqtopo: error: " + bag.string() + ":/odom: ",
                        "the time ranges do not overlap: images 1.000 .. 4.000 s, poses 501.000 .. 504.000 s");
}

}  // namespace
}  // namespace seqtopo
