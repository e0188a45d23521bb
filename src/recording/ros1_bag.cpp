// ROS 1 bags through Debian's librosbag-dev (rosbag_storage) and the generated message classes of
// libsensor-msgs-dev, libnav-msgs-dev and libgeometry-msgs-dev. Compiled as C++17: those headers use
// std::allocator<void>::rebind, which C++20 removed.
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>

#include <exception>
#include <map>
#include <string>

#include "backend.hpp"
#include "seqtopo/core/input_error.hpp"

namespace seqtopo::recording::detail {
namespace {

RosTime stamp_of(const ros::Time& t) {
  RosTime r;
  r.sec = t.sec;
  r.nanosec = t.nsec;
  return r;
}

// rosbag's texts can name its decompressors' internals ("BZ_OUTBUFF_FULL: size of the compressed data exceeds
// *destLen"): a chunk that does not decompress is said in the user's terms; other texts are kept, on one line.
std::string reason(const std::exception& e) {
  std::string what = e.what();
  for (const char* internal : {"destLen", "BZ_", "BZ2", "bzip", "roslz4", "LZ4", "lz4"}) {
    if (what.find(internal) != std::string::npos) {
      return "a compressed chunk does not decompress (the bag is corrupt or was cut short)";
    }
  }
  for (char& c : what) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return what;
}

std::int64_t nanoseconds(const ros::Time& t) { return static_cast<std::int64_t>(t.toNSec()); }

template <typename PoseMsg>
void copy_pose(const PoseMsg& p, RosPose& out) {
  out.x = p.position.x;
  out.y = p.position.y;
  out.z = p.position.z;
  out.qx = p.orientation.x;
  out.qy = p.orientation.y;
  out.qz = p.orientation.z;
  out.qw = p.orientation.w;
}

class Ros1Bag final : public Backend {
 public:
  explicit Ros1Bag(std::string path) : path_(std::move(path)) {
    // Every problem becomes an InputError naming the file; rosbag's own console reports are noise (as
    // OpenCV's are for images).
    console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
    try {
      bag_.open(path_, rosbag::bagmode::Read);
    } catch (const std::exception& e) {
      throw InputError(path_, std::string("cannot read as a ROS 1 bag: ") + reason(e));
    }
  }

  std::vector<Topic> topics() const override {
    std::map<std::string, Topic> by_name;
    try {
      rosbag::View view(bag_);
      for (const rosbag::ConnectionInfo* c : view.getConnections()) {
        Topic& t = by_name[c->topic];
        t.name = c->topic;
        t.type = c->datatype;
      }
      for (auto& [name, t] : by_name) {
        rosbag::View one(bag_, rosbag::TopicQuery(name));
        t.messages = one.size();
      }
    } catch (const std::exception& e) {
      throw InputError(path_, std::string("cannot read the bag's index: ") + reason(e));
    }
    std::vector<Topic> out;
    for (auto& [name, t] : by_name) out.push_back(t);
    return out;
  }

  void read_images(const std::string& topic, bool with_data,
                   const std::function<void(RosImage&, std::int64_t)>& visit) const override {
    each(topic, [&](const rosbag::MessageInstance& m) {
      RosImage out;
      if (auto raw = m.instantiate<sensor_msgs::Image>()) {
        out.stamp = stamp_of(raw->header.stamp);
        out.encoding = raw->encoding;
        out.height = raw->height;
        out.width = raw->width;
        out.step = raw->step;
        out.big_endian = raw->is_bigendian != 0;
        if (with_data) out.data = std::move(raw->data);
      } else if (auto packed = m.instantiate<sensor_msgs::CompressedImage>()) {
        out.compressed = true;
        out.stamp = stamp_of(packed->header.stamp);
        out.format = packed->format;
        if (with_data) out.data = std::move(packed->data);
      } else {
        throw InputError(path_, "topic " + topic + ": " + m.getDataType() + " is not an image message");
      }
      visit(out, nanoseconds(m.getTime()));
    });
  }

  void read_poses(const std::string& topic,
                  const std::function<void(const RosPose&, std::int64_t)>& visit) const override {
    each(topic, [&](const rosbag::MessageInstance& m) {
      RosPose out;
      if (auto odo = m.instantiate<nav_msgs::Odometry>()) {
        out.stamp = stamp_of(odo->header.stamp);
        copy_pose(odo->pose.pose, out);
      } else if (auto ps = m.instantiate<geometry_msgs::PoseStamped>()) {
        out.stamp = stamp_of(ps->header.stamp);
        copy_pose(ps->pose, out);
      } else {
        throw InputError(path_, "topic " + topic + ": " + m.getDataType() + " is not an odometry or pose message");
      }
      visit(out, nanoseconds(m.getTime()));
    });
  }

 private:
  template <typename F>
  void each(const std::string& topic, F&& f) const {
    try {
      rosbag::View view(bag_, rosbag::TopicQuery(topic));
      for (const rosbag::MessageInstance& m : view) f(m);
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {
      throw InputError(path_, "topic " + topic + ": cannot read a message: " + reason(e));
    }
  }

  std::string path_;
  mutable rosbag::Bag bag_;
};

}  // namespace

std::unique_ptr<Backend> open_ros1(const std::string& path) { return std::make_unique<Ros1Bag>(path); }

}  // namespace seqtopo::recording::detail
