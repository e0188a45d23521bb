// The bag readers (recording/recording.hpp) on bags written by independent implementations: topics, counts,
// image times, pixels of every supported encoding, poses, topic choice, and one error naming the file for
// bad bags (truncated, corrupt chunk, unknown encoding, wrong topic).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
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

// metadata.yaml as rosbag2 (metadata version 5) writes it, listing `files` (names without the extension).
void write_metadata(const fs::path& folder, BagKind kind, const std::vector<std::string>& files) {
  std::ofstream out(folder / "metadata.yaml");
  out << "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: "
      << (kind == BagKind::db3 ? "sqlite3" : "mcap") << "\n  relative_file_paths:\n";
  for (const auto& f : files) out << "    - " << f << bag_extension(kind) << "\n";
  out << "  duration:\n    nanoseconds: 0\n  message_count: 0\n  topics_with_message_count: []\n";
}

// A bag split into `parts` files run_0 ... run_<parts - 1>, one 5 x 4 image each at time 100 + k [s].
std::vector<double> write_split_bag(const TempDir& dir, const fs::path& folder, BagKind kind, int parts) {
  fs::create_directories(folder);
  std::vector<double> times;
  for (int k = 0; k < parts; ++k) {
    Recipe recipe;
    const RgbImage image = pattern(5, 4, k);
    const fs::path ppm = dir.path / ("part" + std::to_string(k) + ".ppm");
    test_support::write_ppm(ppm, image);
    recipe.raw_image("/camera", 100.0 + k, ppm, image);
    test_support::write_bag(recipe, kind, folder / ("run_" + std::to_string(k) + bag_extension(kind)));
    times.push_back(100.0 + k);
  }
  return times;
}

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

// A ROS 1 bag whose compressed chunk is damaged or cut: the error says so in the user's terms, not with the
// decompressor's internals ("BZ_OUTBUFF_FULL: size of the compressed data exceeds *destLen").
TEST(Ros1Bag, DamagedCompressedChunkIsSaidWithoutDecompressorInternals) {
  TempDir dir;
  SmallBag small(dir);
  for (const BagKind kind : {BagKind::ros1_bz2, BagKind::ros1_lz4}) {
    const fs::path path = dir.path / (std::string(bag_kind_name(kind)) + ".bag");
    test_support::write_bag(small.recipe, kind, path);
    const std::string bytes = test_support::read_file(path);
    for (const double cut : {0.3, 0.5, 0.7}) {
      for (const bool flip : {false, true}) {
        std::string damaged = bytes;
        const auto at = static_cast<std::size_t>(cut * static_cast<double>(bytes.size()));
        if (flip) {
          for (std::size_t k = at; k < at + 24 && k < damaged.size(); ++k) damaged[k] = static_cast<char>(~damaged[k]);
        } else {
          damaged.resize(at);
        }
        const fs::path bad = dir.path / "damaged.bag";
        std::ofstream(bad, std::ios::binary | std::ios::trunc) << damaged;
        const std::string e = error_of([&] {
          const Recording bag(bad);
          bag.for_each_image(bag.image_topic(), 1, {}, [](std::size_t, double, const RgbImage&) {});
          (void)bag.poses("/odom");
        });
        if (e == "no error") continue;  // a flip in a part nothing reads
        EXPECT_EQ(e.rfind(bad.string() + ": ", 0), 0U) << e;
        for (const char* internal : {"destLen", "BZ_", "LZ4", "roslz4"}) {
          EXPECT_EQ(e.find(internal), std::string::npos) << bag_kind_name(kind) << " " << cut << ": " << e;
        }
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
      }
    }
  }
}

// A ROS 2 bag as ros2 bag record writes it: a folder with metadata.yaml and the storage file(s).
TEST(Ros2BagFolder, ReadAsTheBag) {
  TempDir dir;
  SmallBag small(dir);
  for (const BagKind kind : {BagKind::db3, BagKind::mcap_zstd}) {
    const fs::path folder = dir.path / bag_kind_name(kind);
    fs::create_directory(folder);
    write_metadata(folder, kind, {"run_0"});
    test_support::write_bag(small.recipe, kind, folder / ("run_0" + bag_extension(kind)));
    const Recording bag(folder);
    EXPECT_EQ(bag.format(), kind == BagKind::db3 ? BagFormat::ros2_sqlite : BagFormat::ros2_mcap);
    EXPECT_EQ(bag.image_topic(), "/camera");
    EXPECT_EQ(bag.image_times("/camera").size(), 3U);
    EXPECT_TRUE(looks_like_recording(folder));
  }
}

// A bag split into 12 files (issue #47, finding 1): run_10 and run_11 come after run_9, as metadata.yaml lists
// them, not after run_1 as the names sort; without metadata.yaml the names' natural order (strverscmp) gives
// the same.
TEST(Ros2BagFolder, SplitBagIsReadInTheOrderOfItsFiles) {
  TempDir dir;
  for (const BagKind kind : {BagKind::db3, BagKind::mcap_zstd}) {
    const fs::path folder = dir.path / (std::string("split_") + bag_kind_name(kind));
    const std::vector<double> times = write_split_bag(dir, folder, kind, 12);
    std::vector<std::string> names;
    for (int k = 0; k < 12; ++k) names.push_back("run_" + std::to_string(k));
    write_metadata(folder, kind, names);
    EXPECT_EQ(Recording(folder).image_times("/camera"), times) << bag_kind_name(kind);
    std::vector<std::uint8_t> seeds;
    Recording(folder).for_each_image(
        "/camera", 1, {}, [&](std::size_t, double, const RgbImage& image) { seeds.push_back(image.at(0, 0)[0]); });
    ASSERT_EQ(seeds.size(), 12U);
    for (int k = 0; k < 12; ++k) EXPECT_EQ(seeds[static_cast<std::size_t>(k)], pattern(5, 4, k).at(0, 0)[0]) << k;
    // The order metadata.yaml gives is the order read, whatever the names.
    std::vector<std::string> reversed(names.rbegin(), names.rend());
    write_metadata(folder, kind, reversed);
    EXPECT_EQ(Recording(folder).image_times("/camera"), std::vector<double>(times.rbegin(), times.rend()));
    fs::remove(folder / "metadata.yaml");
    EXPECT_EQ(Recording(folder).image_times("/camera"), times) << bag_kind_name(kind) << " without metadata.yaml";
  }
}

// Storage files beside the bag that metadata.yaml does not list (a backup copy) are not read, as ros2 bag play
// does not read them; Recording names them (the map command says so in a note).
TEST(Ros2BagFolder, FilesMetadataDoesNotListAreNotRead) {
  TempDir dir;
  for (const BagKind kind : {BagKind::db3, BagKind::mcap_zstd}) {
    const fs::path folder = dir.path / (std::string("stray_") + bag_kind_name(kind));
    const std::vector<double> times = write_split_bag(dir, folder, kind, 3);
    write_metadata(folder, kind, {"run_0", "run_1"});
    const fs::path copy = folder / ("run_1 copy" + bag_extension(kind));
    fs::copy_file(folder / ("run_1" + bag_extension(kind)), copy);
    const Recording bag(folder);
    EXPECT_EQ(bag.image_times("/camera"), (std::vector<double>{times[0], times[1]})) << bag_kind_name(kind);
    EXPECT_EQ(bag.message_count("/camera"), 2U);
    std::vector<fs::path> unlisted = bag.unlisted_files();
    EXPECT_EQ(unlisted, (std::vector<fs::path>{copy, folder / ("run_2" + bag_extension(kind))}));
  }
}

// A metadata.yaml that is not rosbag2's is refused with one line naming it, never read around.
TEST(Ros2BagFolder, BadMetadataIsAnErrorNamingIt) {
  TempDir dir;
  const fs::path folder = dir.path / "bag";
  write_split_bag(dir, folder, BagKind::db3, 2);
  const std::string yaml = (folder / "metadata.yaml").string();
  const auto error_with = [&](const std::string& text) {
    std::ofstream(folder / "metadata.yaml", std::ios::trunc) << text;
    const std::string e = error_of([&] { (void)Recording(folder); });
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    return e;
  };
  EXPECT_EQ(error_with("rosbag2_bagfile_information: [unclosed\n").rfind(yaml + ": not YAML", 0), 0U);
  EXPECT_EQ(error_with(std::string("\x89PNG\r\n\x1a\n\0\0garbage{{{", 16)).rfind(yaml + ": ", 0), 0U);
  EXPECT_EQ(error_with("just some text\n"),
            yaml + ": not a rosbag2 metadata file (no rosbag2_bagfile_information mapping)");
  EXPECT_EQ(error_with("rosbag2_bagfile_information:\n  version: 5\n"),
            yaml + ": rosbag2_bagfile_information.relative_file_paths does not list the bag's files");
  EXPECT_EQ(error_with("rosbag2_bagfile_information:\n  version: 5\n  relative_file_paths: [run_0.db3, run_7.db3]\n"),
            yaml + ": lists run_7.db3, which is missing");
  EXPECT_EQ(error_with("rosbag2_bagfile_information:\n  version: 5\n  relative_file_paths: [run_0.db3, run_0.db3]\n"),
            yaml + ": lists run_0.db3 twice");
  EXPECT_EQ(error_with("rosbag2_bagfile_information:\n  version: x\n  relative_file_paths: [run_0.db3]\n"),
            yaml + ": rosbag2_bagfile_information.version is 'x', not a version number");
  // rosbag2 before version 4 wrote the paths with the bag folder's name.
  std::ofstream(folder / "metadata.yaml", std::ios::trunc)
      << "rosbag2_bagfile_information:\n  version: 3\n  relative_file_paths:\n    - bag/run_1.db3\n    - "
         "bag/run_0.db3\n";
  EXPECT_EQ(Recording(folder).image_times("/camera"), (std::vector<double>{101.0, 100.0}));
}

// MCAP messages stored out of log-time order (issue #47, finding 3) are read in log-time order, as .db3 ones are:
// the same bag in both storages gives the same times and images. Small chunks put the late ones in other chunks.
TEST(Mcap, MessagesAreReadInLogTimeOrder) {
  TempDir dir;
  Recipe recipe;
  const std::vector<double> stored{100.5, 100.0, 103.0, 101.0, 102.5, 102.0, 101.5, 103.0};
  for (std::size_t k = 0; k < stored.size(); ++k) {
    const RgbImage image = pattern(5, 4, static_cast<int>(k));
    const fs::path ppm = dir.path / ("u" + std::to_string(k) + ".ppm");
    test_support::write_ppm(ppm, image);
    recipe.raw_image("/camera", stored[k], ppm, image);
  }
  recipe.options = {{"keep_order", true}, {"chunk_size", 200}};
  std::vector<std::size_t> order(stored.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return stored[a] < stored[b]; });
  for (const BagKind kind : {BagKind::mcap_zstd, BagKind::mcap_lz4, BagKind::mcap_none, BagKind::db3}) {
    const fs::path path = dir.path / (std::string("unsorted_") + bag_kind_name(kind) + bag_extension(kind));
    test_support::write_bag(recipe, kind, path);
    const Recording bag(path);
    std::vector<double> times;
    std::vector<std::uint8_t> seeds;
    bag.for_each_image("/camera", 1, {}, [&](std::size_t, double t, const RgbImage& image) {
      times.push_back(t);
      seeds.push_back(image.at(0, 0)[0]);
    });
    ASSERT_EQ(times.size(), stored.size()) << bag_kind_name(kind);
    for (std::size_t k = 0; k < order.size(); ++k) {
      EXPECT_EQ(times[k], stored[order[k]]) << bag_kind_name(kind) << " " << k;
      // Ties (two at 103.0) in the order stored.
      EXPECT_EQ(seeds[k], pattern(5, 4, static_cast<int>(order[k])).at(0, 0)[0]) << bag_kind_name(kind) << " " << k;
    }
    EXPECT_EQ(bag.image_times("/camera"), times);
  }
}

// The same instant from a header stamp and from the bag's log time (the stamp 0) is the same double, not
// 1e-9 * ns against sec + 1e-9 * nsec, an ulp apart at 1700140891.611178002 s.
TEST(Ros2Bag, StampAndLogTimeOfOneInstantAreEqual) {
  TempDir dir;
  Recipe recipe;
  const RgbImage image = pattern(5, 4, 1);
  const fs::path ppm = dir.path / "i.ppm";
  test_support::write_ppm(ppm, image);
  recipe.raw_image("/camera", 0.0, ppm, image);
  recipe.topics[0]["messages"][0]["sec"] = 1700140891;
  recipe.topics[0]["messages"][0]["nanosec"] = 611178002;
  recipe.raw_image("/camera", 0.0, ppm, image);  // stamp 0: the log time stands for it
  recipe.topics[0]["messages"][1]["log_time"] = "1700140891612178002";
  recipe.raw_image("/camera", 0.0, ppm, image);
  recipe.topics[0]["messages"][2]["log_time"] = "1700140891611178002";
  for (const BagKind kind : {BagKind::db3, BagKind::mcap_zstd}) {
    const fs::path path = dir.path / (std::string("instant_") + bag_kind_name(kind) + bag_extension(kind));
    test_support::write_bag(recipe, kind, path);
    const auto times = Recording(path).image_times("/camera");
    ASSERT_EQ(times.size(), 3U);
    // In log-time order: the stamped one (its log time is its stamp), then the zero stamps by log time.
    EXPECT_EQ(times[0], times[1]) << bag_kind_name(kind);
    EXPECT_EQ(times[0], 1700140891.0 + 1e-9 * 611178002.0) << bag_kind_name(kind);
    EXPECT_GT(times[2], times[1]);
  }
}

// An MCAP whose summary counts more messages than its data holds: the error names the file, the topic and the
// summary, not the odometry that later disagrees with the frame count.
TEST(Mcap, SummaryThatDisagreesWithTheDataIsAnError) {
  TempDir dir;
  SmallBag small(dir);
  const fs::path path = dir.path / "summary.mcap";
  test_support::write_bag(small.recipe, BagKind::mcap_zstd, path);
  std::string bytes = test_support::read_file(path);
  // Footer: opcode 0x02, length 20, summary_start, summary_offset_start, summary_crc; then the closing magic.
  const std::size_t footer = bytes.size() - 8 - 29;
  ASSERT_EQ(static_cast<std::uint8_t>(bytes[footer]), 0x02);
  std::uint64_t at = 0;
  std::memcpy(&at, bytes.data() + footer + 9, 8);
  bool patched = false;
  while (at + 9 <= footer && !patched) {
    std::uint64_t length = 0;
    std::memcpy(&length, bytes.data() + at + 1, 8);
    if (static_cast<std::uint8_t>(bytes[at]) == 0x0B) {
      // message_count (u64), counts (u16 + 4 x u32), start and end times (2 x u64), then the channel counts.
      char* stats = bytes.data() + at + 9;
      std::uint64_t total = 0;
      std::memcpy(&total, stats, 8);
      char* map = stats + 8 + 2 + 16 + 16;
      std::uint32_t map_bytes = 0;
      std::memcpy(&map_bytes, map, 4);
      for (std::uint32_t k = 0; k < map_bytes; k += 10) {
        std::uint64_t n = 0;
        std::memcpy(&n, map + 4 + k + 2, 8);
        n += 2;
        total += 2;
        std::memcpy(map + 4 + k + 2, &n, 8);
      }
      std::memcpy(stats, &total, 8);
      patched = true;
    }
    at += 9 + length;
  }
  ASSERT_TRUE(patched);
  std::memset(bytes.data() + footer + 9 + 16, 0, 4);  // no summary CRC
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  const Recording bag(path);
  EXPECT_EQ(bag.message_count("/camera"), 5U);  // the summary's word
  EXPECT_EQ(error_of([&] { (void)bag.image_times("/camera"); }),
            path.string() +
                ": topic /camera: the summary's Statistics record counts 5 messages, the data section "
                "holds 3 (a damaged or rewritten MCAP file)");
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
