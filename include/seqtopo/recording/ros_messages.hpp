#pragma once
// The ROS messages seqtopo reads from bags, as plain data, whatever the bag's serialization (ROS 1 or CDR):
// sensor_msgs/Image and sensor_msgs/CompressedImage (the image sequence), nav_msgs/Odometry and
// geometry_msgs/PoseStamped (the odometry). C++17-clean on purpose: the ROS 1 reader is compiled as C++17,
// which Debian's ROS 1 message headers need.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace seqtopo::recording {

// What a topic carries, by ROS type name with or without "/msg/" (ROS 1 "sensor_msgs/Image", ROS 2
// "sensor_msgs/msg/Image").
enum class MessageType { image, compressed_image, odometry, pose_stamped, other };
MessageType message_type(std::string_view type_name);
inline bool is_image(MessageType t) { return t == MessageType::image || t == MessageType::compressed_image; }
inline bool is_pose(MessageType t) { return t == MessageType::odometry || t == MessageType::pose_stamped; }

struct RosTime {
  std::int64_t sec = 0;
  std::uint32_t nanosec = 0;
  bool zero() const { return sec == 0 && nanosec == 0; }
  double seconds() const { return static_cast<double>(sec) + 1e-9 * static_cast<double>(nanosec); }
};

// sensor_msgs/Image (raw pixels) or sensor_msgs/CompressedImage (compressed = true: `format` and the encoded
// bytes in `data`).
struct RosImage {
  RosTime stamp;  // header.stamp
  bool compressed = false;
  std::string encoding;  // raw: mono8, mono16, rgb8, bgr8, rgba8, bgra8, 8UC1, 8UC3, 16UC1
  std::uint32_t height = 0, width = 0, step = 0;
  bool big_endian = false;
  std::string format;  // compressed: "jpeg", "png", "rgb8; jpeg compressed bgr8", ...
  std::vector<std::uint8_t> data;
};

// The pose of nav_msgs/Odometry (pose.pose) or geometry_msgs/PoseStamped (pose).
struct RosPose {
  RosTime stamp;
  double x = 0, y = 0, z = 0;
  double qx = 0, qy = 0, qz = 0, qw = 1;
};

}  // namespace seqtopo::recording
