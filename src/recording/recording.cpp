#include "seqtopo/recording/recording.hpp"

#include <string.h>  // strverscmp (glibc)
#include <yaml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <new>
#include <set>
#include <system_error>

#include "backend.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/lower_case.hpp"
#include "seqtopo/core/text_file.hpp"
#include "seqtopo/image/image_io.hpp"

namespace seqtopo::recording {

namespace fs = std::filesystem;

std::string_view bag_format_name(BagFormat format) {
  switch (format) {
    case BagFormat::ros1:
      return "ROS 1 bag";
    case BagFormat::ros2_sqlite:
      return "ROS 2 bag (SQLite)";
    case BagFormat::ros2_mcap:
      return "ROS 2 bag (MCAP)";
  }
  return "?";
}

namespace {

std::string extension(const fs::path& p) { return lower_case(p.extension().string()); }

// The storage files of a ROS 2 bag folder with extension `ext`, in natural order (glibc's strverscmp:
// run_2.db3 before run_10.db3), for a folder without metadata.yaml.
std::vector<std::string> storage_files(const fs::path& folder, const std::string& ext) {
  std::vector<std::string> files;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    if (extension(entry.path()) == ext) files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end(),
            [](const std::string& a, const std::string& b) { return ::strverscmp(a.c_str(), b.c_str()) < 0; });
  return files;
}

// A YAML document loaded by libyaml; node() is nullptr for a missing node.
class YamlDocument {
 public:
  YamlDocument(const std::string& text, const std::string& subject) {
    yaml_parser_t parser;
    if (!yaml_parser_initialize(&parser)) throw std::bad_alloc();
    yaml_parser_set_input_string(&parser, reinterpret_cast<const unsigned char*>(text.data()), text.size());
    const bool ok = yaml_parser_load(&parser, &document_) != 0;
    std::string why;
    if (!ok) {
      why = std::string("not YAML: ") + (parser.problem ? parser.problem : "parse error") + " at line " +
            std::to_string(parser.problem_mark.line + 1);
    }
    yaml_parser_delete(&parser);
    if (!ok) throw InputError(subject, why);
    loaded_ = true;
  }
  ~YamlDocument() {
    if (loaded_) yaml_document_delete(&document_);
  }
  YamlDocument(const YamlDocument&) = delete;
  YamlDocument& operator=(const YamlDocument&) = delete;

  yaml_node_t* root() { return yaml_document_get_root_node(&document_); }
  // The value of `key` in the mapping `map`, or nullptr.
  yaml_node_t* get(yaml_node_t* map, std::string_view key) {
    if (map == nullptr || map->type != YAML_MAPPING_NODE) return nullptr;
    for (auto* pair = map->data.mapping.pairs.start; pair < map->data.mapping.pairs.top; ++pair) {
      const yaml_node_t* k = yaml_document_get_node(&document_, pair->key);
      if (k && k->type == YAML_SCALAR_NODE && scalar(k) == key) return yaml_document_get_node(&document_, pair->value);
    }
    return nullptr;
  }
  std::vector<yaml_node_t*> items(yaml_node_t* sequence) {
    std::vector<yaml_node_t*> out;
    for (auto* item = sequence->data.sequence.items.start; item < sequence->data.sequence.items.top; ++item) {
      out.push_back(yaml_document_get_node(&document_, *item));
    }
    return out;
  }
  static std::string scalar(const yaml_node_t* n) {
    return {reinterpret_cast<const char*>(n->data.scalar.value), n->data.scalar.length};
  }

 private:
  yaml_document_t document_{};
  bool loaded_ = false;
};

struct BagFolder {
  std::vector<std::string> files;  // the storage files to read, in order
  std::string ext;                 // ".db3" or ".mcap"
  std::vector<fs::path> unlisted;  // storage files beside them that metadata.yaml does not list
};

// The storage files metadata.yaml lists under rosbag2_bagfile_information.relative_file_paths, in its order
// (as rosbag2 plays them); a metadata file that does not parse or lists no file is refused, as ros2 bag does.
BagFolder listed_storage_files(const fs::path& folder) {
  const fs::path metadata = folder / "metadata.yaml";
  const std::string subject = metadata.string();
  YamlDocument doc(read_text_file(metadata, "rosbag2 metadata file", std::size_t{16} << 20U), subject);
  yaml_node_t* info = doc.get(doc.root(), "rosbag2_bagfile_information");
  if (info == nullptr || info->type != YAML_MAPPING_NODE) {
    throw InputError(subject, "not a rosbag2 metadata file (no rosbag2_bagfile_information mapping)");
  }
  // rosbag2 before metadata version 4 wrote the paths relative to the bag folder's parent.
  int version = 5;
  if (yaml_node_t* v = doc.get(info, "version"); v && v->type == YAML_SCALAR_NODE) {
    const std::string text = YamlDocument::scalar(v);
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), version);
    if (error != std::errc{} || end != text.data() + text.size() || version < 1) {
      throw InputError(subject, "rosbag2_bagfile_information.version is '" + text + "', not a version number");
    }
  }
  const fs::path base = version < 4 ? folder.parent_path() : folder;
  yaml_node_t* paths = doc.get(info, "relative_file_paths");
  if (paths == nullptr || paths->type != YAML_SEQUENCE_NODE || doc.items(paths).empty()) {
    throw InputError(subject, "rosbag2_bagfile_information.relative_file_paths does not list the bag's files");
  }
  BagFolder out;
  std::set<fs::path> read;
  for (yaml_node_t* item : doc.items(paths)) {
    if (item == nullptr || item->type != YAML_SCALAR_NODE || YamlDocument::scalar(item).empty()) {
      throw InputError(subject, "relative_file_paths holds an entry that is not a file name");
    }
    const std::string name = YamlDocument::scalar(item);
    const fs::path file = fs::path(name).is_absolute() ? fs::path(name) : base / name;
    const std::string ext = extension(file);
    if (ext != ".db3" && ext != ".mcap") {
      throw InputError(subject, "lists " + name +
                                    ", not a .db3 or .mcap storage file (file-compressed bags are "
                                    "not read: decompress them with ros2 bag convert)");
    }
    if (!out.ext.empty() && ext != out.ext) throw InputError(subject, "lists both .db3 and .mcap files");
    out.ext = ext;
    if (const std::string why = special_file_reason(file); !why.empty()) {
      throw InputError(subject, "lists " + name + ", which is " + (why == "no such file" ? "missing" : why));
    }
    if (!read.insert(fs::weakly_canonical(file)).second) throw InputError(subject, "lists " + name + " twice");
    out.files.push_back(file.string());
  }
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string ext = extension(entry.path());
    if ((ext == ".db3" || ext == ".mcap") && !read.count(fs::weakly_canonical(entry.path(), ec))) {
      out.unlisted.push_back(entry.path());
    }
  }
  std::sort(out.unlisted.begin(), out.unlisted.end(),
            [](const fs::path& a, const fs::path& b) { return ::strverscmp(a.c_str(), b.c_str()) < 0; });
  return out;
}

std::string listed(const std::vector<TopicInfo>& topics, bool (*keep)(MessageType)) {
  std::string out;
  for (const auto& t : topics) {
    if (!keep(message_type(t.type))) continue;
    out += (out.empty() ? "" : ", ") + t.name + " (" + t.type + ")";
  }
  return out.empty() ? "none" : out;
}

bool any_image(MessageType t) { return is_image(t); }
bool any_pose(MessageType t) { return is_pose(t); }

const TopicInfo* find_topic(const std::vector<TopicInfo>& topics, std::string_view name) {
  for (const auto& t : topics) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

// A log time [ns] as a stamp: whole seconds and nanoseconds, so that the same instant gives the same double
// whether it comes from a header stamp or the bag's log time (1e-9 * ns differs from sec + 1e-9 * nsec by an ulp).
RosTime stamp_of_ns(std::int64_t ns) {
  RosTime t;
  t.sec = ns / 1000000000;
  std::int64_t rest = ns % 1000000000;
  if (rest < 0) {
    rest += 1000000000;
    --t.sec;
  }
  t.nanosec = static_cast<std::uint32_t>(rest);
  return t;
}

double time_of(const RosTime& stamp, std::int64_t log_time_ns) {
  return stamp.zero() ? stamp_of_ns(log_time_ns).seconds() : stamp.seconds();
}

}  // namespace

bool looks_like_recording(const fs::path& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    return fs::exists(path / "metadata.yaml", ec) &&
           (!storage_files(path, ".db3").empty() || !storage_files(path, ".mcap").empty());
  }
  const std::string ext = extension(path);
  return ext == ".bag" || ext == ".db3" || ext == ".mcap";
}

Recording::Recording(const fs::path& path) : path_(path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path.string(), "no such file or folder");
  std::string ext = extension(path);
  std::vector<std::string> files{path.string()};
  if (fs::is_directory(path, ec)) {
    if (fs::exists(path / "metadata.yaml", ec)) {
      BagFolder folder = listed_storage_files(path);
      files = std::move(folder.files);
      ext = folder.ext;
      unlisted_ = std::move(folder.unlisted);
    } else {
      files = storage_files(path, ".db3");
      ext = ".db3";
      if (files.empty()) {
        files = storage_files(path, ".mcap");
        ext = ".mcap";
      }
    }
    if (files.empty()) throw InputError(path.string(), "a ROS 2 bag folder holds .db3 or .mcap files; found none");
  } else if (const std::string why = special_file_reason(path); !why.empty()) {
    throw InputError(path.string(), why + ", not a bag");
  }
  if (ext == ".bag") {
    format_ = BagFormat::ros1;
    backend_ = detail::open_ros1(path.string());
  } else if (ext == ".db3") {
    format_ = BagFormat::ros2_sqlite;
    backend_ = detail::open_ros2_sqlite(files, path.string());
  } else if (ext == ".mcap") {
    format_ = BagFormat::ros2_mcap;
    backend_ = detail::open_ros2_mcap(files, path.string());
  } else {
    throw InputError(path.string(), "not a bag: expected a .bag, .db3 or .mcap file or a ROS 2 bag folder");
  }
  for (const auto& t : backend_->topics()) topics_.push_back({t.name, t.type, t.messages});
}

Recording::~Recording() = default;
Recording::Recording(Recording&&) noexcept = default;
Recording& Recording::operator=(Recording&&) noexcept = default;

std::string Recording::image_topic(std::string_view requested) const {
  if (!requested.empty()) {
    const TopicInfo* t = find_topic(topics_, requested);
    if (!t) {
      throw InputError(path_.string(), "no topic " + std::string(requested) +
                                           " in the bag; its image topics: " + listed(topics_, any_image));
    }
    if (!is_image(message_type(t->type))) {
      throw InputError(path_.string(), "topic " + t->name + " holds " + t->type +
                                           ", not sensor_msgs/Image or CompressedImage; the bag's image topics: " +
                                           listed(topics_, any_image));
    }
    return t->name;
  }
  std::vector<const TopicInfo*> images;
  for (const auto& t : topics_) {
    if (is_image(message_type(t.type))) images.push_back(&t);
  }
  if (images.empty()) {
    std::string all;
    for (const auto& t : topics_) all += (all.empty() ? "" : ", ") + t.name + " (" + t.type + ")";
    throw InputError(path_.string(), "the bag has no sensor_msgs/Image or CompressedImage topic (topics: " +
                                         (all.empty() ? std::string("none") : all) + ")");
  }
  if (images.size() > 1) {
    throw InputError(path_.string(),
                     "the bag has several image topics, choose one with --image-topic: " + listed(topics_, any_image));
  }
  return images.front()->name;
}

std::optional<std::string> Recording::odometry_topic(std::string_view requested) const {
  if (requested == "none") return std::nullopt;
  if (!requested.empty()) {
    const TopicInfo* t = find_topic(topics_, requested);
    if (!t || !is_pose(message_type(t->type))) {
      throw InputError(path_.string(),
                       (t ? "topic " + t->name + " holds " + t->type + ", not nav_msgs/Odometry or PoseStamped"
                          : "no topic " + std::string(requested) + " in the bag") +
                           "; its odometry topics: " + listed(topics_, any_pose));
    }
    return t->name;
  }
  std::vector<const TopicInfo*> poses;
  for (const auto& t : topics_) {
    if (is_pose(message_type(t.type))) poses.push_back(&t);
  }
  if (poses.empty()) return std::nullopt;
  if (poses.size() > 1) {
    throw InputError(path_.string(),
                     "the bag has several odometry topics, choose one with --odometry-topic (or none): " +
                         listed(topics_, any_pose));
  }
  return poses.front()->name;
}

std::size_t Recording::message_count(const std::string& topic) const {
  const TopicInfo* t = find_topic(topics_, topic);
  return t ? static_cast<std::size_t>(t->messages) : 0;
}

std::vector<double> Recording::image_times(const std::string& topic) const {
  std::vector<double> times;
  backend_->read_images(topic, false,
                        [&](RosImage& m, std::int64_t log_time) { times.push_back(time_of(m.stamp, log_time)); });
  return times;
}

std::vector<TimedPose> Recording::poses(const std::string& topic) const {
  std::vector<TimedPose> out;
  std::size_t index = 0;
  backend_->read_poses(topic, [&](const RosPose& p, std::int64_t log_time) {
    const double norm = std::sqrt(p.qx * p.qx + p.qy * p.qy + p.qz * p.qz + p.qw * p.qw);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(norm) || std::abs(norm - 1.0) > 1e-3) {
      throw InputError(path_.string(), "topic " + topic + ", message " + std::to_string(index) +
                                           ": the pose is not finite or its quaternion is not of unit length");
    }
    const double yaw = std::atan2(2.0 * (p.qw * p.qz + p.qx * p.qy), 1.0 - 2.0 * (p.qy * p.qy + p.qz * p.qz));
    out.push_back({time_of(p.stamp, log_time), {p.x, p.y, wrap_angle(yaw)}});
    ++index;
  });
  std::stable_sort(out.begin(), out.end(), [](const TimedPose& a, const TimedPose& b) { return a.time < b.time; });
  out.erase(
      std::unique(out.begin(), out.end(), [](const TimedPose& a, const TimedPose& b) { return a.time == b.time; }),
      out.end());
  if (out.empty()) throw InputError(path_.string(), "topic " + topic + " holds no message");
  return out;
}

void Recording::for_each_image(const std::string& topic, std::size_t every, std::span<const std::size_t> frames,
                               const std::function<void(std::size_t, double, const RgbImage&)>& visit) const {
  if (every == 0) throw std::invalid_argument("every must be at least 1");
  std::size_t index = 0, next = 0;
  bool any = false;
  backend_->read_images(topic, true, [&](RosImage& m, std::int64_t log_time) {
    const std::size_t k = index++;
    if (k % every != 0) return;
    const std::size_t kept = k / every;
    if (!frames.empty()) {
      if (next >= frames.size() || frames[next] != kept) return;
      ++next;
    }
    const std::string subject = path_.string();
    RgbImage image;
    try {
      image = to_rgb(m, subject);
    } catch (const InputError& e) {
      throw InputError(subject, "topic " + topic + ", image " + std::to_string(k) + ": " + e.what());
    }
    any = true;
    visit(k, time_of(m.stamp, log_time), image);
  });
  if (!any) throw InputError(path_.string(), "topic " + topic + " holds no image");
}

namespace {
struct StopReading {};  // not a std::exception: passes through the backends' error handling
}  // namespace

void Recording::check_first_image(const std::string& topic) const {
  try {
    backend_->read_images(topic, true, [&](RosImage& m, std::int64_t) {
      try {
        (void)to_rgb(m, path_.string());
      } catch (const InputError& e) {
        throw InputError(path_.string(), "topic " + topic + ", image 0: " + e.what());
      }
      throw StopReading{};
    });
  } catch (const StopReading&) {
    return;
  }
  throw InputError(path_.string(), "topic " + topic + " holds no image");
}

RgbImage to_rgb(const RosImage& m, const std::string& subject) {
  if (m.compressed) {
    const auto image = image::decode_image(m.data, subject);
    return image;
  }
  const std::string& e = m.encoding;
  int channels = 0, bytes = 1;
  if (e == "mono8" || e == "8UC1") {
    channels = 1;
  } else if (e == "mono16" || e == "16UC1") {
    channels = 1;
    bytes = 2;
  } else if (e == "rgb8" || e == "bgr8" || e == "8UC3") {
    channels = 3;
  } else if (e == "rgba8" || e == "bgra8") {
    channels = 4;
  } else {
    throw InputError(subject, "image encoding '" + e +
                                  "' is not supported (mono8, mono16, rgb8, bgr8, rgba8, bgra8, or a CompressedImage)");
  }
  if (m.width == 0 || m.height == 0 || m.width > 1U << 16U || m.height > 1U << 16U) {
    throw InputError(subject, "image of " + std::to_string(m.width) + " x " + std::to_string(m.height) +
                                  " pixels is empty or implausible");
  }
  const std::size_t row = static_cast<std::size_t>(m.width) * static_cast<std::size_t>(channels * bytes);
  if (m.step < row || m.data.size() < static_cast<std::size_t>(m.step) * (m.height - 1) + row) {
    throw InputError(subject, "image data of " + std::to_string(m.data.size()) + " bytes does not hold " +
                                  std::to_string(m.width) + " x " + std::to_string(m.height) + " " + e +
                                  " pixels with step " + std::to_string(m.step));
  }
  const bool bgr = e == "bgr8" || e == "8UC3" || e == "bgra8";
  RgbImage out(static_cast<int>(m.width), static_cast<int>(m.height));
  for (std::uint32_t y = 0; y < m.height; ++y) {
    const std::uint8_t* src = m.data.data() + static_cast<std::size_t>(y) * m.step;
    for (std::uint32_t x = 0; x < m.width; ++x) {
      std::uint8_t* dst = out.at(static_cast<int>(x), static_cast<int>(y));
      if (bytes == 2) {
        const std::uint8_t* p = src + 2 * x;
        const unsigned v = m.big_endian ? (unsigned{p[0]} << 8U) | p[1] : (unsigned{p[1]} << 8U) | p[0];
        const auto g = static_cast<std::uint8_t>(std::lround(static_cast<double>(v) / 257.0));
        dst[0] = dst[1] = dst[2] = g;
      } else if (channels == 1) {
        dst[0] = dst[1] = dst[2] = src[x];
      } else {
        const std::uint8_t* p = src + static_cast<std::size_t>(x) * static_cast<std::size_t>(channels);
        dst[0] = bgr ? p[2] : p[0];
        dst[1] = p[1];
        dst[2] = bgr ? p[0] : p[2];
      }
    }
  }
  return out;
}

}  // namespace seqtopo::recording
