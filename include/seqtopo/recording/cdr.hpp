#pragma once
// CDR, the serialization of ROS 2 messages (OMG DDS-XTypes 1.3, section 7.4 "Data Representation"; ROS 2
// stores plain CDR, XCDR1, with a 4-byte encapsulation header: 00 00 big-endian, 00 01 little-endian;
// 00 06 / 00 07 are plain XCDR2, whose 8-byte values align to 4). Primitives align to their size, counted
// from the end of the encapsulation header; a string is a uint32 length including its NUL, then the bytes; a
// sequence a uint32 count then the elements.
//
// Decoders for the four messages seqtopo reads (ros_messages.hpp). Every decoder throws
// std::invalid_argument with what is wrong ("truncated: string of 4096 bytes at offset 20 runs past the end of
// the 64-byte message") on malformed bytes; the bag readers add the file and topic.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "seqtopo/recording/ros_messages.hpp"

namespace seqtopo::recording {

class CdrReader {
 public:
  // `message` starts with the encapsulation header.
  explicit CdrReader(std::span<const std::uint8_t> message);
  std::uint8_t u8();
  std::uint32_t u32();
  std::int32_t i32();
  double f64();
  std::string string();
  std::span<const std::uint8_t> bytes();  // sequence<uint8>
  std::size_t offset() const { return at_; }
  std::size_t size() const { return data_.size(); }

 private:
  void align(std::size_t size);
  std::span<const std::uint8_t> take(std::size_t n, const char* what);
  std::span<const std::uint8_t> data_;
  std::size_t at_ = 4;
  bool little_ = true;
  std::size_t max_align_ = 8;
};

RosImage decode_image_cdr(std::span<const std::uint8_t> message);             // sensor_msgs/msg/Image
RosImage decode_compressed_image_cdr(std::span<const std::uint8_t> message);  // sensor_msgs/msg/CompressedImage
RosPose decode_odometry_cdr(std::span<const std::uint8_t> message);           // nav_msgs/msg/Odometry
RosPose decode_pose_stamped_cdr(std::span<const std::uint8_t> message);       // geometry_msgs/msg/PoseStamped
// The header stamp alone (every message above starts with std_msgs/Header).
RosTime decode_stamp_cdr(std::span<const std::uint8_t> message);

}  // namespace seqtopo::recording
