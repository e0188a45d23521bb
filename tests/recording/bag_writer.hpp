#pragma once
// Test bags written by independent implementations (tests/recording/*.py, *.mjs): a recipe of topics and
// messages in JSON, then Debian's python3-rosbag (ROS 1), @mcap/core + @foxglove/rosmsg2-serialization (MCAP)
// or those CDR messages put into SQLite by Python's sqlite3 (.db3).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/run_command.hpp"
#include "seqtopo/core/rgb_image.hpp"

namespace seqtopo::test_support {

// mcap_none: uncompressed chunks and no Statistics record (the reader then scans the data section for counts).
enum class BagKind { ros1, ros1_bz2, ros1_lz4, db3, mcap_zstd, mcap_lz4, mcap_none };
inline const char* bag_kind_name(BagKind k) {
  switch (k) {
    case BagKind::ros1:
      return "ros1";
    case BagKind::ros1_bz2:
      return "ros1_bz2";
    case BagKind::ros1_lz4:
      return "ros1_lz4";
    case BagKind::db3:
      return "db3";
    case BagKind::mcap_zstd:
      return "mcap_zstd";
    case BagKind::mcap_lz4:
      return "mcap_lz4";
    case BagKind::mcap_none:
      return "mcap_none";
  }
  return "?";
}
inline std::string bag_extension(BagKind k) {
  return k == BagKind::ros1 || k == BagKind::ros1_bz2 || k == BagKind::ros1_lz4 ? ".bag"
         : k == BagKind::db3                                                    ? ".db3"
                                                                                : ".mcap";
}
inline const std::vector<BagKind>& all_bag_kinds() {
  static const std::vector<BagKind> kinds{BagKind::ros1,      BagKind::ros1_bz2, BagKind::ros1_lz4, BagKind::db3,
                                          BagKind::mcap_zstd, BagKind::mcap_lz4, BagKind::mcap_none};
  return kinds;
}

inline std::string base64(const std::vector<std::uint8_t>& bytes) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t k = 0;
  for (; k + 2 < bytes.size(); k += 3) {
    const unsigned v = (unsigned{bytes[k]} << 16U) | (unsigned{bytes[k + 1]} << 8U) | bytes[k + 2];
    for (int s = 18; s >= 0; s -= 6) out += alphabet[(v >> static_cast<unsigned>(s)) & 63U];
  }
  if (k < bytes.size()) {
    const unsigned v = (unsigned{bytes[k]} << 16U) | (k + 1 < bytes.size() ? unsigned{bytes[k + 1]} << 8U : 0U);
    out += alphabet[(v >> 18U) & 63U];
    out += alphabet[(v >> 12U) & 63U];
    out += k + 1 < bytes.size() ? alphabet[(v >> 6U) & 63U] : '=';
    out += '=';
  }
  return out;
}

inline void write_ppm(const std::filesystem::path& path, const RgbImage& image) {
  std::ofstream out(path, std::ios::binary);
  out << "P6\n" << image.width << " " << image.height << "\n255\n";
  out.write(reinterpret_cast<const char*>(image.pixels.data()), static_cast<std::streamsize>(image.pixels.size()));
}

// A recipe: {"topics": [{"name", "type", "messages": [...]}]} (tests/recording/write_ros2_bag.mjs).
struct Recipe {
  nlohmann::json topics = nlohmann::json::array();
  // Writer options beside the topics: "chunk_size" (MCAP bytes per chunk), "keep_order" (true: the messages are
  // stored in the recipe's order, not sorted by time, as a recorder with late messages stores them).
  nlohmann::json options = nlohmann::json::object();
  nlohmann::json& topic(const std::string& name, const std::string& type) {
    for (auto& t : topics) {
      if (t["name"] == name) return t;
    }
    topics.push_back({{"name", name}, {"type", type}, {"messages", nlohmann::json::array()}});
    return topics.back();
  }
  static nlohmann::json stamp(double t) {
    const auto sec = static_cast<std::int64_t>(std::floor(t));
    auto nsec = static_cast<std::int64_t>(std::llround((t - static_cast<double>(sec)) * 1e9));
    return {{"sec", sec}, {"nanosec", nsec}};
  }
  void raw_image(const std::string& name, double t, const std::filesystem::path& ppm, const RgbImage& image,
                 const std::string& encoding = "rgb8") {
    auto m = stamp(t);
    m.update({{"width", image.width},
              {"height", image.height},
              {"encoding", encoding},
              {"step", 3 * image.width},
              {"ppm", ppm.string()}});
    topic(name, "sensor_msgs/msg/Image")["messages"].push_back(m);
  }
  void raw_bytes(const std::string& name, double t, int width, int height, const std::string& encoding, int step,
                 const std::vector<std::uint8_t>& data, bool big_endian = false) {
    auto m = stamp(t);
    m.update({{"width", width},
              {"height", height},
              {"encoding", encoding},
              {"step", step},
              {"is_bigendian", big_endian ? 1 : 0},
              {"raw", base64(data)}});
    topic(name, "sensor_msgs/msg/Image")["messages"].push_back(m);
  }
  void compressed(const std::string& name, double t, const std::filesystem::path& file, const std::string& format) {
    auto m = stamp(t);
    m.update({{"format", format}, {"file", file.string()}});
    topic(name, "sensor_msgs/msg/CompressedImage")["messages"].push_back(m);
  }
  void pose(const std::string& name, const std::string& type, double t, double x, double y, double yaw) {
    auto m = stamp(t);
    m.update({{"x", x}, {"y", y}, {"yaw", yaw}});
    topic(name, type)["messages"].push_back(m);
  }
};

inline std::string shell_quoted(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

// Writes `recipe` as a bag of `kind` at `out` (its extension added by the caller); fails the test on error.
inline void write_bag(const Recipe& recipe, BagKind kind, const std::filesystem::path& out) {
  const std::filesystem::path recipe_path = out.string() + ".json";
  nlohmann::json document = recipe.options;
  document["topics"] = recipe.topics;
  std::ofstream(recipe_path) << document.dump();
  const std::string source = std::string(SEQTOPO_SOURCE_DIR) + "/tests/recording/";
  const std::string node = std::string(SEQTOPO_NODE) + " " + SEQTOPO_RECORDING_TOOLS + "/write_ros2_bag.mjs ";
  std::string command;
  switch (kind) {
    case BagKind::ros1:
    case BagKind::ros1_bz2:
    case BagKind::ros1_lz4:
      command = std::string(SEQTOPO_SYSTEM_PYTHON3) + " " + source + "write_ros1_bag.py " + shell_quoted(recipe_path) +
                " " + shell_quoted(out) + " " +
                (kind == BagKind::ros1_bz2   ? "bz2"
                 : kind == BagKind::ros1_lz4 ? "lz4"
                                             : "none");
      break;
    case BagKind::db3:
      command = node + shell_quoted(recipe_path) + " cdr " +
                shell_quoted(std::filesystem::path(out.string() + ".cdr")) + " && " + SEQTOPO_SYSTEM_PYTHON3 + " " +
                source + "write_db3.py " + shell_quoted(std::filesystem::path(out.string() + ".cdr")) + " " +
                shell_quoted(out);
      break;
    case BagKind::mcap_zstd:
    case BagKind::mcap_lz4:
    case BagKind::mcap_none:
      command = node + shell_quoted(recipe_path) + " mcap " + shell_quoted(out) + " " +
                (kind == BagKind::mcap_zstd  ? "zstd"
                 : kind == BagKind::mcap_lz4 ? "lz4"
                                             : "none");
      break;
  }
  const CommandResult r = run_command(command);
  ASSERT_EQ(r.status, 0) << command << "\n" << r.err;
}

// Flips 16 bytes in the middle of the first Chunk record (opcode 0x06) of an MCAP file written by @mcap/core
// (magic, Header, then the chunks); fails the test when there is none.
inline void corrupt_first_chunk(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  std::size_t at = 8;
  while (at + 9 <= bytes.size()) {
    std::uint64_t length = 0;
    std::memcpy(&length, bytes.data() + at + 1, 8);
    if (static_cast<std::uint8_t>(bytes[at]) == 0x06) {
      const std::size_t middle = at + 9 + static_cast<std::size_t>(length) / 2;
      for (std::size_t k = middle; k < middle + 16 && k < bytes.size(); ++k) bytes[k] = static_cast<char>(~bytes[k]);
      std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
      return;
    }
    at += 9 + static_cast<std::size_t>(length);
  }
  FAIL() << path << " has no chunk";
}

}  // namespace seqtopo::test_support
