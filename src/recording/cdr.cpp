#include "seqtopo/recording/cdr.hpp"

#include <cstring>
#include <stdexcept>

namespace seqtopo::recording {

MessageType message_type(std::string_view type_name) {
  std::string name(type_name);
  if (const auto at = name.find("/msg/"); at != std::string::npos) name.erase(at, 4);
  if (name == "sensor_msgs/Image") return MessageType::image;
  if (name == "sensor_msgs/CompressedImage") return MessageType::compressed_image;
  if (name == "nav_msgs/Odometry") return MessageType::odometry;
  if (name == "geometry_msgs/PoseStamped") return MessageType::pose_stamped;
  return MessageType::other;
}

CdrReader::CdrReader(std::span<const std::uint8_t> message) : data_(message) {
  if (message.size() < 4) {
    throw std::invalid_argument("truncated: " + std::to_string(message.size()) +
                                " bytes, shorter than the 4-byte CDR encapsulation header");
  }
  const std::uint8_t kind = message[1];
  if (message[0] != 0 || (kind != 0x00 && kind != 0x01 && kind != 0x06 && kind != 0x07)) {
    throw std::invalid_argument("unsupported CDR encapsulation " + std::to_string(message[0]) + " " +
                                std::to_string(kind) + " (expected plain CDR: 0 0, 0 1, 0 6 or 0 7)");
  }
  little_ = (kind & 1U) != 0;
  max_align_ = kind >= 0x06 ? 4 : 8;
}

void CdrReader::align(std::size_t size) {
  const std::size_t a = std::min(size, max_align_);
  const std::size_t origin = 4;  // alignment counts from the end of the encapsulation header
  const std::size_t rel = at_ - origin;
  at_ = origin + (rel + a - 1) / a * a;
}

std::span<const std::uint8_t> CdrReader::take(std::size_t n, const char* what) {
  if (at_ > data_.size() || n > data_.size() - at_) {
    throw std::invalid_argument(std::string("truncated: ") + what + " of " + std::to_string(n) + " bytes at offset " +
                                std::to_string(at_) + " runs past the end of the " + std::to_string(data_.size()) +
                                "-byte message");
  }
  const auto out = data_.subspan(at_, n);
  at_ += n;
  return out;
}

namespace {
template <typename T>
T load(std::span<const std::uint8_t> b, bool little) {
  std::uint8_t tmp[sizeof(T)];
  for (std::size_t k = 0; k < sizeof(T); ++k) tmp[k] = little ? b[k] : b[sizeof(T) - 1 - k];  // host is little-endian
  T v;
  std::memcpy(&v, tmp, sizeof(T));
  return v;
}
}  // namespace

std::uint8_t CdrReader::u8() { return take(1, "uint8")[0]; }
std::uint32_t CdrReader::u32() {
  align(4);
  return load<std::uint32_t>(take(4, "uint32"), little_);
}
std::int32_t CdrReader::i32() {
  align(4);
  return load<std::int32_t>(take(4, "int32"), little_);
}
double CdrReader::f64() {
  align(8);
  return load<double>(take(8, "float64"), little_);
}
std::string CdrReader::string() {
  const std::uint32_t n = u32();
  const auto b = take(n, "string");
  std::size_t len = b.size();
  if (len > 0 && b[len - 1] == 0) --len;  // the terminating NUL
  return std::string(reinterpret_cast<const char*>(b.data()), len);
}
std::span<const std::uint8_t> CdrReader::bytes() {
  const std::uint32_t n = u32();
  return take(n, "byte sequence");
}

namespace {

RosTime read_header(CdrReader& r) {
  RosTime t;
  t.sec = r.i32();
  t.nanosec = r.u32();
  (void)r.string();  // frame_id
  return t;
}

void pose(CdrReader& r, RosPose& p) {
  p.x = r.f64();
  p.y = r.f64();
  p.z = r.f64();
  p.qx = r.f64();
  p.qy = r.f64();
  p.qz = r.f64();
  p.qw = r.f64();
}

}  // namespace

RosImage decode_image_cdr(std::span<const std::uint8_t> message) {
  CdrReader r(message);
  RosImage m;
  m.stamp = read_header(r);
  m.height = r.u32();
  m.width = r.u32();
  m.encoding = r.string();
  m.big_endian = r.u8() != 0;
  m.step = r.u32();
  const auto data = r.bytes();
  m.data.assign(data.begin(), data.end());
  return m;
}

RosImage decode_compressed_image_cdr(std::span<const std::uint8_t> message) {
  CdrReader r(message);
  RosImage m;
  m.compressed = true;
  m.stamp = read_header(r);
  m.format = r.string();
  const auto data = r.bytes();
  m.data.assign(data.begin(), data.end());
  return m;
}

RosPose decode_odometry_cdr(std::span<const std::uint8_t> message) {
  CdrReader r(message);
  RosPose p;
  p.stamp = read_header(r);
  (void)r.string();  // child_frame_id
  pose(r, p);        // pose.pose; the covariance and the twist follow
  return p;
}

RosPose decode_pose_stamped_cdr(std::span<const std::uint8_t> message) {
  CdrReader r(message);
  RosPose p;
  p.stamp = read_header(r);
  pose(r, p);
  return p;
}

RosTime decode_stamp_cdr(std::span<const std::uint8_t> message) {
  CdrReader r(message);
  RosTime t;
  t.sec = r.i32();
  t.nanosec = r.u32();
  return t;
}

}  // namespace seqtopo::recording
