#pragma once
// The three bag storages behind recording.hpp: ROS 1 (librosbag), ROS 2 SQLite (.db3) and ROS 2 MCAP.
// C++17-clean (ros1_bag.cpp is compiled as C++17 for Debian's ROS 1 message headers).
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "seqtopo/recording/ros_messages.hpp"

namespace seqtopo::recording::detail {

struct Topic {
  std::string name, type;
  std::uint64_t messages = 0;
};

class Backend {
 public:
  virtual ~Backend() = default;
  virtual std::vector<Topic> topics() const = 0;
  // visit(message, log_time_ns) for every image of `topic` in the file's order; with_data = false may leave the
  // pixels out (times only). Bad messages throw InputError naming the file and the topic.
  virtual void read_images(const std::string& topic, bool with_data,
                           const std::function<void(RosImage&, std::int64_t)>& visit) const = 0;
  virtual void read_poses(const std::string& topic,
                          const std::function<void(const RosPose&, std::int64_t)>& visit) const = 0;
};

std::unique_ptr<Backend> open_ros1(const std::string& path);
// One or more storage files of one ROS 2 bag (split bags), in order; `subject` names the bag in errors.
std::unique_ptr<Backend> open_ros2_sqlite(const std::vector<std::string>& files, const std::string& subject);
std::unique_ptr<Backend> open_ros2_mcap(const std::vector<std::string>& files, const std::string& subject);

}  // namespace seqtopo::recording::detail
