// The bag readers (recording/recording.hpp) on bags written by independent implementations: topics, counts,
// image times, pixels of every supported encoding, poses, topic choice, and one error naming the file for
// bad bags (truncated, corrupt chunk, unknown encoding, wrong topic).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "bag_writer.hpp"
#include "common/input_error_text.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/image/image_io.hpp"
#include "seqtopo/recording/cdr.hpp"
#include "seqtopo/recording/mcap_reader.hpp"
#include "seqtopo/recording/recording.hpp"

namespace seqtopo::recording {
namespace {

namespace fs = std::filesystem;
using test_support::all_bag_kinds;
using test_support::bag_extension;
using test_support::bag_kind_name;
using test_support::BagKind;
using test_support::Recipe;
using test_support::TempDir;

RgbImage pattern(int w, int h, int seed) {
  RgbImage image(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      auto* p = image.at(x, y);
      p[0] = static_cast<std::uint8_t>(17 * x + 5 * y + seed);
      p[1] = static_cast<std::uint8_t>(3 * x * y + 7 * seed);
      p[2] = static_cast<std::uint8_t>(255 - 11 * x - seed);
    }
  }
  return image;
}

using test_support::error_of;

// Three rgb8 images on /camera, odometry on /odom (4 poses, other times), a PoseStamped on /pose.
struct SmallBag {
  std::vector<RgbImage> images{pattern(5, 4, 1), pattern(5, 4, 2), pattern(5, 4, 3)};
  std::vector<double> times{100.25, 100.5, 101.0};
  Recipe recipe;
  explicit SmallBag(const TempDir& dir) {
    for (std::size_t k = 0; k < images.size(); ++k) {
      const fs::path ppm = dir.path / ("small" + std::to_string(k) + ".ppm");
      test_support::write_ppm(ppm, images[k]);
      recipe.raw_image("/camera", times[k], ppm, images[k]);
    }
    for (int k = 0; k < 4; ++k) recipe.pose("/odom", "nav_msgs/msg/Odometry", 100.0 + 0.5 * k, k, -k, 0.25 * k);
    recipe.pose("/pose", "geometry_msgs/msg/PoseStamped", 100.0, 1, 2, 0.5);
  }
};

class Readers : public ::testing::TestWithParam<BagKind> {};

TEST_P(Readers, TopicsTimesPixelsPoses) {
  TempDir dir;
  SmallBag small(dir);
  const fs::path path = dir.path / ("small" + bag_extension(GetParam()));
  test_support::write_bag(small.recipe, GetParam(), path);
  const Recording bag(path);
  ASSERT_EQ(bag.topics().size(), 3U);
  EXPECT_EQ(bag.message_count("/camera"), 3U);
  EXPECT_EQ(bag.message_count("/odom"), 4U);
  EXPECT_EQ(bag.image_topic(), "/camera");
  // Two odometry topics: the choice is the user's.
  const std::string several = error_of([&] { (void)bag.odometry_topic(); });
  EXPECT_NE(several.find("several odometry topics"), std::string::npos) << several;
  EXPECT_NE(several.find("/odom (nav_msgs"), std::string::npos) << several;
  EXPECT_NE(several.find("/pose (geometry_msgs"), std::string::npos) << several;
  EXPECT_EQ(bag.odometry_topic("none"), std::nullopt);
  EXPECT_EQ(bag.odometry_topic("/pose"), "/pose");
  EXPECT_NE(error_of([&] { (void)bag.odometry_topic("/camera"); }).find("not nav_msgs/Odometry"), std::string::npos);

  const auto times = bag.image_times("/camera");
  ASSERT_EQ(times.size(), 3U);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(times[k], small.times[k], 1e-9);
  std::vector<std::size_t> seen;
  bag.for_each_image("/camera", 1, {}, [&](std::size_t k, double t, const RgbImage& image) {
    seen.push_back(k);
    EXPECT_NEAR(t, small.times[k], 1e-9);
    EXPECT_EQ(image.pixels, small.images[k].pixels) << "image " << k;
  });
  EXPECT_EQ(seen, (std::vector<std::size_t>{0, 1, 2}));
  seen.clear();
  const std::vector<std::size_t> frames{1};
  bag.for_each_image("/camera", 2, frames, [&](std::size_t k, double, const RgbImage&) { seen.push_back(k); });
  EXPECT_EQ(seen, (std::vector<std::size_t>{2}));  // every 2nd image, then kept frame 1 of those

  const auto poses = bag.poses("/odom");
  ASSERT_EQ(poses.size(), 4U);
  for (int k = 0; k < 4; ++k) {
    EXPECT_DOUBLE_EQ(poses[k].time, 100.0 + 0.5 * k);
    EXPECT_DOUBLE_EQ(poses[k].pose.x, k);
    EXPECT_DOUBLE_EQ(poses[k].pose.y, -k);
    EXPECT_NEAR(poses[k].pose.theta, 0.25 * k, 1e-12);
  }
  const auto pose = bag.poses("/pose");
  ASSERT_EQ(pose.size(), 1U);
  EXPECT_NEAR(pose[0].pose.theta, 0.5, 1e-12);
}

TEST_P(Readers, EncodingsAndTopicChoice) {
  TempDir dir;
  Recipe r;
  // 3 x 2 pixels: mono8, mono16 both byte orders, bgr8 with row padding, rgba8, and an unsupported yuv422.
  const std::vector<std::uint8_t> mono8{0, 50, 100, 150, 200, 255};
  r.raw_bytes("/mono8", 1.0, 3, 2, "mono8", 3, mono8);
  std::vector<std::uint8_t> le, be;
  const std::vector<unsigned> mono16{0, 257, 1000, 40000, 65535, 128};
  for (unsigned v : mono16) {
    le.insert(le.end(), {static_cast<std::uint8_t>(v & 255U), static_cast<std::uint8_t>(v >> 8U)});
    be.insert(be.end(), {static_cast<std::uint8_t>(v >> 8U), static_cast<std::uint8_t>(v & 255U)});
  }
  r.raw_bytes("/mono16le", 1.0, 3, 2, "mono16", 6, le);
  r.raw_bytes("/mono16be", 1.0, 3, 2, "mono16", 6, be, true);
  std::vector<std::uint8_t> bgr;
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 3; ++x) bgr.insert(bgr.end(), {std::uint8_t(10 * x), std::uint8_t(20 + y), std::uint8_t(200)});
    bgr.insert(bgr.end(), {9, 9});  // padding: step 11
  }
  r.raw_bytes("/bgr8", 1.0, 3, 2, "bgr8", 11, bgr);
  r.raw_bytes("/yuv", 1.0, 3, 2, "yuv422", 6, std::vector<std::uint8_t>(12, 1));
  const RgbImage png_image = pattern(6, 5, 9);
  const fs::path png = dir.path / "frame.png";
  {
    // A PNG written by hand-picked bytes would be long; OpenCV's encoder writes it (the reader must decode).
    std::ofstream(png, std::ios::binary) << "";
  }
  test_support::write_ppm(dir.path / "frame.ppm", png_image);
  r.compressed("/compressed", 1.0, dir.path / "frame.ppm", "ppm");
  const fs::path path = dir.path / ("enc" + bag_extension(GetParam()));
  test_support::write_bag(r, GetParam(), path);
  const Recording bag(path);

  const std::string choose = error_of([&] { (void)bag.image_topic(); });
  EXPECT_NE(choose.find(path.string() + ": the bag has several image topics, choose one with --image-topic"),
            std::string::npos)
      << choose;
  for (const char* t : {"/mono8", "/mono16le", "/bgr8", "/compressed"}) EXPECT_NE(choose.find(t), std::string::npos);
  const std::string missing = error_of([&] { (void)bag.image_topic("/nope"); });
  EXPECT_NE(missing.find("no topic /nope in the bag; its image topics: /bgr8 (sensor_msgs"), std::string::npos)
      << missing;

  auto first = [&](const std::string& topic) {
    RgbImage out;
    bag.for_each_image(bag.image_topic(topic), 1, {}, [&](std::size_t, double, const RgbImage& image) { out = image; });
    return out;
  };
  const RgbImage m8 = first("/mono8");
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(m8.pixels[3 * k], mono8[k]);
    EXPECT_EQ(m8.pixels[3 * k + 2], mono8[k]);
  }
  const RgbImage m16le = first("/mono16le"), m16be = first("/mono16be");
  EXPECT_EQ(m16le.pixels, m16be.pixels);
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(m16le.pixels[3 * k], static_cast<std::uint8_t>(std::lround(mono16[k] / 257.0))) << k;
  }
  const RgbImage b = first("/bgr8");
  EXPECT_EQ(b.pixels[3 * 4 + 0], 200);  // pixel (1, 1): R is the third byte
  EXPECT_EQ(b.pixels[3 * 4 + 1], 21);
  EXPECT_EQ(b.pixels[3 * 4 + 2], 10);
  EXPECT_EQ(first("/compressed").pixels, png_image.pixels);
  const std::string yuv = error_of([&] { (void)first("/yuv"); });
  EXPECT_NE(yuv.find(path.string() + ": topic /yuv, image 0: image encoding 'yuv422' is not supported"),
            std::string::npos)
      << yuv;
}

TEST_P(Readers, TruncatedBagIsAnErrorNamingTheFile) {
  TempDir dir;
  SmallBag small(dir);
  const fs::path path = dir.path / ("small" + bag_extension(GetParam()));
  test_support::write_bag(small.recipe, GetParam(), path);
  const auto size = fs::file_size(path);
  for (const double keep : {0.6, 0.2}) {
    const fs::path cut = dir.path / ("cut" + std::to_string(static_cast<int>(keep * 10)) + bag_extension(GetParam()));
    fs::copy_file(path, cut);
    fs::resize_file(cut, static_cast<std::uintmax_t>(keep * static_cast<double>(size)));
    const std::string e = error_of([&] {
      const Recording bag(cut);
      bag.for_each_image(bag.image_topic(), 1, {}, [](std::size_t, double, const RgbImage&) {});
      (void)bag.poses("/odom");
    });
    EXPECT_EQ(e.rfind(cut.string() + ": ", 0), 0U) << keep << ": " << e;
  }
}

// A ROS 2 bag as ros2 bag record writes it: a folder with metadata.yaml and the storage file(s).
TEST(Ros2BagFolder, ReadAsTheBag) {
  TempDir dir;
  SmallBag small(dir);
  for (const BagKind kind : {BagKind::db3, BagKind::mcap_zstd}) {
    const fs::path folder = dir.path / bag_kind_name(kind);
    fs::create_directory(folder);
    std::ofstream(folder / "metadata.yaml") << "rosbag2_bagfile_information:\n  version: 5\n";
    test_support::write_bag(small.recipe, kind, folder / ("run_0" + bag_extension(kind)));
    const Recording bag(folder);
    EXPECT_EQ(bag.format(), kind == BagKind::db3 ? BagFormat::ros2_sqlite : BagFormat::ros2_mcap);
    EXPECT_EQ(bag.image_topic(), "/camera");
    EXPECT_EQ(bag.image_times("/camera").size(), 3U);
    EXPECT_TRUE(looks_like_recording(folder));
  }
}

INSTANTIATE_TEST_SUITE_P(AllFormats, Readers, ::testing::ValuesIn(all_bag_kinds()),
                         [](const auto& info) { return std::string(bag_kind_name(info.param)); });

// A compressed MCAP chunk with bytes flipped in its middle: the decompressor or the CRC catches it.
TEST(Mcap, CorruptChunkIsAnErrorNamingTheFile) {
  TempDir dir;
  SmallBag small(dir);
  for (const BagKind kind : {BagKind::mcap_zstd, BagKind::mcap_lz4, BagKind::mcap_none}) {
    const fs::path path = dir.path / (std::string(bag_kind_name(kind)) + ".mcap");
    test_support::write_bag(small.recipe, kind, path);
    std::string bytes = test_support::read_file(path);
    // The chunk is the first big record after the header: flip a stretch in the middle of the file's first half.
    for (std::size_t k = bytes.size() / 4; k < bytes.size() / 4 + 16; ++k)
      bytes[k] = static_cast<char>(bytes[k] ^ 0x5A);
    const fs::path bad = dir.path / (std::string(bag_kind_name(kind)) + "-bad.mcap");
    std::ofstream(bad, std::ios::binary) << bytes;
    const std::string e = error_of([&] {
      const Recording bag(bad);
      bag.for_each_image(bag.image_topic(), 1, {}, [](std::size_t, double, const RgbImage&) {});
    });
    EXPECT_EQ(e.rfind(bad.string() + ": ", 0), 0U) << e;
    EXPECT_NE(e.find("chunk"), std::string::npos) << bag_kind_name(kind) << ": " << e;
  }
}

TEST(Mcap, ReaderSeesSchemasChannelsCounts) {
  TempDir dir;
  SmallBag small(dir);
  for (const BagKind kind : {BagKind::mcap_zstd, BagKind::mcap_none}) {  // with and without Statistics
    const fs::path path = dir.path / (std::string(bag_kind_name(kind)) + ".mcap");
    test_support::write_bag(small.recipe, kind, path);
    const McapReader reader(path);
    EXPECT_EQ(reader.profile(), "ros2");
    ASSERT_EQ(reader.channels().size(), 3U);
    std::map<std::string, std::uint64_t> counts;
    for (const auto& [id, c] : reader.channels()) {
      counts[c.topic] = reader.message_counts().at(id);
      EXPECT_EQ(c.message_encoding, "cdr");
      EXPECT_EQ(reader.schemas().at(c.schema_id).encoding, "ros2msg");
    }
    EXPECT_EQ(counts, (std::map<std::string, std::uint64_t>{{"/camera", 3}, {"/odom", 4}, {"/pose", 1}}));
    std::size_t messages = 0;
    std::uint64_t last = 0;
    reader.for_each_message([&](const McapChannel&, const McapMessage& m) {
      ++messages;
      EXPECT_GE(m.log_time, last);
      last = m.log_time;
    });
    EXPECT_EQ(messages, 8U);
  }
  const fs::path path = dir.path / "mcap_zstd.mcap";
  EXPECT_EQ(error_of([&] { McapReader(small.recipe.topics.empty() ? path : dir.path / "small0.ppm"); }),
            (dir.path / "small0.ppm").string() + ": not an MCAP file (no MCAP magic at its start)");
}

TEST(Cdr, AlignmentAndTruncation) {
  // Little-endian CDR: uint8 7 at offset 4, then a float64 aligned to 8 counted from the end of the 4-byte
  // header (offset 12, after 7 bytes of padding), then a uint32 at offset 20.
  std::vector<std::uint8_t> m{0, 1, 0, 0, 7, 0xEE, 0xEE, 0xEE, 0xEE, 0xEE, 0xEE, 0xEE};
  const double v = 2.5;
  std::uint8_t b[8];
  std::memcpy(b, &v, 8);
  m.insert(m.end(), b, b + 8);
  m.insert(m.end(), {0x2A, 0, 0, 0});
  CdrReader r(m);
  EXPECT_EQ(r.u8(), 7);
  EXPECT_EQ(r.f64(), 2.5);
  EXPECT_EQ(r.u32(), 42U);
  try {
    (void)r.u32();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "truncated: uint32 of 4 bytes at offset 24 runs past the end of the 24-byte message");
  }
  EXPECT_THROW(CdrReader(std::vector<std::uint8_t>{0, 1}), std::invalid_argument);
  EXPECT_THROW(CdrReader(std::vector<std::uint8_t>{0, 9, 0, 0}), std::invalid_argument);  // not plain CDR
}

}  // namespace
}  // namespace seqtopo::recording
