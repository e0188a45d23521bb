#pragma once
// A robot's recording (docs/recordings.md): a ROS 1 bag (.bag, librosbag), a ROS 2 bag in SQLite (.db3) or
// MCAP (.mcap) storage, or a ROS 2 bag folder (metadata.yaml beside its storage files). Its image topic
// (sensor_msgs/Image in mono8, mono16, rgb8, bgr8, rgba8, bgra8, or sensor_msgs/CompressedImage) is the
// image sequence; its nav_msgs/Odometry or geometry_msgs/PoseStamped topic the odometry.
//
//   recording::Recording bag("run.bag");
//   const std::string topic = bag.image_topic();              // the only image topic, or an error listing them
//   bag.for_each_image(topic, 1, {}, [&](std::size_t k, double t, const RgbImage& image) { ... });
//
// Image times are the messages' header stamps (the bag's receive time when a stamp is 0) [s].
// Every error is an InputError naming the file and the problem: not a bag, truncated, corrupt chunk, no
// such topic (with the candidates), an unsupported encoding, a malformed message.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "seqtopo/core/rgb_image.hpp"
#include "seqtopo/core/timed_pose.hpp"
#include "seqtopo/recording/ros_messages.hpp"

namespace seqtopo::recording {

namespace detail {
class Backend;
}

enum class BagFormat { ros1, ros2_sqlite, ros2_mcap };
std::string_view bag_format_name(BagFormat format);

struct TopicInfo {
  std::string name, type;
  std::uint64_t messages = 0;
};

class Recording {
 public:
  explicit Recording(const std::filesystem::path& path);
  ~Recording();
  Recording(Recording&&) noexcept;
  Recording& operator=(Recording&&) noexcept;

  const std::filesystem::path& path() const { return path_; }
  BagFormat format() const { return format_; }
  const std::vector<TopicInfo>& topics() const { return topics_; }
  // A ROS 2 bag folder's storage files that its metadata.yaml does not list (a copy beside the recording):
  // not read, as ros2 bag play does not read them.
  const std::vector<std::filesystem::path>& unlisted_files() const { return unlisted_; }

  // `requested` when given (it must be an image topic of the bag), else the bag's only image topic. Throws
  // InputError listing the image topics when there are none, several, or `requested` is not one of them.
  std::string image_topic(std::string_view requested = {}) const;
  // `requested` when given ("none" = no odometry), else the bag's only Odometry / PoseStamped topic, or
  // nullopt when it has none. Throws InputError listing them when there are several or `requested` is not
  // one of them.
  std::optional<std::string> odometry_topic(std::string_view requested = {}) const;

  // The number of messages on a topic, from the bag's index.
  std::size_t message_count(const std::string& topic) const;
  // The time of every image of `topic` [s], in file order.
  std::vector<double> image_times(const std::string& topic) const;
  // The poses of an odometry topic, sorted by time (messages at the same time as the previous one are
  // dropped). Throws InputError on a quaternion that is not a rotation.
  std::vector<TimedPose> poses(const std::string& topic) const;
  // Decodes the first image of `topic` (a check before long work: an unsupported encoding fails here).
  // Throws InputError as for_each_image does.
  void check_first_image(const std::string& topic) const;
  // visit(k, time, image) for the images k = 0, every, 2 * every, ... of `topic` (counted in file order),
  // limited to the kept indices k / every in `frames` when it is not empty (increasing).
  void for_each_image(const std::string& topic, std::size_t every, std::span<const std::size_t> frames,
                      const std::function<void(std::size_t, double, const RgbImage&)>& visit) const;

 private:
  std::filesystem::path path_;
  BagFormat format_ = BagFormat::ros1;
  std::unique_ptr<detail::Backend> backend_;
  std::vector<TopicInfo> topics_;
  std::vector<std::filesystem::path> unlisted_;
};

// Whether `path` is a recording by its name: a .bag, .db3 or .mcap file, or a folder with metadata.yaml and a
// .db3 or .mcap file.
bool looks_like_recording(const std::filesystem::path& path);

// The pixels of a decoded message as 8-bit RGB: raw encodings mono8/8UC1, mono16/16UC1 (scaled by 1/257 as
// image::load_image does for 16-bit files), rgb8, bgr8/8UC3, rgba8, bgra8, rows `step` bytes apart; compressed
// ones decoded by OpenCV (image::decode_image). Throws InputError naming `subject` on an unsupported encoding
// or a data size that does not match.
RgbImage to_rgb(const RosImage& message, const std::string& subject);

}  // namespace seqtopo::recording
