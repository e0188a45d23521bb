#include "seqtopo/formats/pose_files.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/text_file.hpp"
#include "seqtopo/formats/odometry_csv.hpp"
#include "seqtopo/io/csv.hpp"
#include "trim.hpp"

namespace seqtopo::formats {
namespace {

namespace fs = std::filesystem;

using detail::trim;

bool skipped(std::string_view line) {
  line = trim(line);
  return line.empty() || line.front() == '#';
}

std::vector<std::string_view> split_on(std::string_view line, char comma) {
  std::vector<std::string_view> fields;
  if (comma == ',') {
    for (;;) {
      const auto at = line.find(',');
      fields.push_back(trim(line.substr(0, at)));
      if (at == std::string_view::npos) return fields;
      line.remove_prefix(at + 1);
    }
  }
  std::size_t k = 0;
  while (k < line.size()) {
    while (k < line.size() && (line[k] == ' ' || line[k] == '\t' || line[k] == '\r')) ++k;
    const std::size_t start = k;
    while (k < line.size() && line[k] != ' ' && line[k] != '\t' && line[k] != '\r') ++k;
    if (k > start) fields.push_back(line.substr(start, k - start));
  }
  return fields;
}

std::string where(const fs::path& path, std::size_t line) { return path.string() + ":" + std::to_string(line); }

double number(const fs::path& path, std::size_t line, std::string_view field, const std::string& name) {
  std::string_view text = field;
  if (text.size() > 1 && text.front() == '+') text.remove_prefix(1);
  double v = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc() || ptr != end) {
    throw InputError(where(path, line), name + " is not a number: '" + std::string(field) + "'");
  }
  if (!std::isfinite(v)) throw InputError(where(path, line), name + " is not finite");
  return v;
}

// Calls row(line_no, fields) for every line that is not blank nor a comment.
template <typename F>
void for_each_line(const fs::path& path, char separator, F&& row) {
  std::istringstream in(read_text_file(path, "pose file"));
  io::skip_byte_order_mark(in);
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (skipped(line)) continue;
    row(line_no, split_on(line, separator));
  }
}

void check_time_order(const fs::path& path, std::size_t line, double t, const std::vector<TimedPose>& so_far) {
  if (!so_far.empty() && !(t > so_far.back().time)) {
    throw InputError(where(path, line), "timestamp " + std::to_string(t) + " does not come after the previous row's " +
                                            std::to_string(so_far.back().time) + " (rows must be in time order)");
  }
}

bool is_time_name(std::string_view s) { return s == "timestamp" || s == "time" || s == "t"; }

}  // namespace

std::string_view pose_file_kind_name(PoseFileKind kind) {
  switch (kind) {
    case PoseFileKind::index_csv:
      return "index CSV";
    case PoseFileKind::timestamped_csv:
      return "timestamped CSV";
    case PoseFileKind::tum:
      return "TUM";
    case PoseFileKind::kitti:
      return "KITTI";
  }
  return "?";
}

std::optional<double> yaw_of_quaternion(double qx, double qy, double qz, double qw) {
  const double norm = std::sqrt(qx * qx + qy * qy + qz * qz + qw * qw);
  if (!std::isfinite(norm) || std::abs(norm - 1.0) > 1e-3) return std::nullopt;
  return std::atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz));
}

std::vector<TimedPose> read_timestamped_csv(const fs::path& path) {
  std::vector<std::string> header;
  std::vector<TimedPose> poses;
  for_each_line(path, ',', [&](std::size_t line, const std::vector<std::string_view>& f) {
    if (header.empty()) {
      const bool ok = (f.size() == 3 || f.size() == 4) && is_time_name(f[0]) && f[1] == "x" && f[2] == "y" &&
                      (f.size() == 3 || f[3] == "yaw" || f[3] == "theta");
      if (!ok) throw InputError(where(path, line), "header must be `timestamp,x,y,yaw` (or theta, or no heading)");
      header.assign(f.begin(), f.end());
      return;
    }
    if (f.size() != header.size()) {
      throw InputError(where(path, line), "expected " + std::to_string(header.size()) +
                                              " comma-separated fields, found " + std::to_string(f.size()));
    }
    double v[4] = {0, 0, 0, 0};
    for (std::size_t k = 0; k < f.size(); ++k) v[k] = number(path, line, f[k], "field '" + header[k] + "'");
    check_time_order(path, line, v[0], poses);
    poses.push_back({v[0], {v[1], v[2], wrap_angle(v[3])}});
  });
  if (header.empty()) throw InputError(path.string(), "empty file; header must be `timestamp,x,y,yaw`");
  if (poses.empty()) throw InputError(path.string(), "no rows after the header");
  return poses;
}

std::vector<TimedPose> read_tum(const fs::path& path) {
  static const char* const names[] = {"timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};
  std::vector<TimedPose> poses;
  for_each_line(path, ' ', [&](std::size_t line, const std::vector<std::string_view>& f) {
    if (f.size() != 8) {
      throw InputError(where(path, line), "a TUM line has 8 numbers (timestamp tx ty tz qx qy qz qw), found " +
                                              std::to_string(f.size()) + " fields");
    }
    double v[8];
    for (std::size_t k = 0; k < 8; ++k) v[k] = number(path, line, f[k], names[k]);
    const auto yaw = yaw_of_quaternion(v[4], v[5], v[6], v[7]);
    if (!yaw) throw InputError(where(path, line), "the quaternion qx qy qz qw is not of unit length");
    check_time_order(path, line, v[0], poses);
    poses.push_back({v[0], {v[1], v[2], wrap_angle(*yaw)}});
  });
  if (poses.empty()) throw InputError(path.string(), "no poses");
  return poses;
}

std::vector<Pose2> read_kitti_poses(const fs::path& path) {
  std::vector<Pose2> poses;
  for_each_line(path, ' ', [&](std::size_t line, const std::vector<std::string_view>& f) {
    if (f.size() != 12) {
      throw InputError(where(path, line), "a KITTI pose line has 12 numbers (the 3 x 4 matrix row by row), found " +
                                              std::to_string(f.size()) + " fields");
    }
    double m[12];
    for (std::size_t k = 0; k < 12; ++k) m[k] = number(path, line, f[k], "number " + std::to_string(k + 1));
    // Camera frame: x right, y down, z forward; the ground plane is (z, -x). The camera's forward axis is
    // the third column of R: (m[2], m[6], m[10]).
    poses.push_back({m[11], -m[3], wrap_angle(std::atan2(-m[2], m[10]))});
  });
  if (poses.empty()) throw InputError(path.string(), "no poses");
  return poses;
}

std::vector<double> read_times_txt(const fs::path& path) {
  std::vector<double> times;
  for_each_line(path, ' ', [&](std::size_t line, const std::vector<std::string_view>& f) {
    if (f.size() != 1) {
      throw InputError(where(path, line), "expected one time per line, found " + std::to_string(f.size()) + " fields");
    }
    const double t = number(path, line, f[0], "time");
    if (!times.empty() && !(t > times.back())) {
      throw InputError(where(path, line), "time " + std::string(f[0]) + " does not come after the previous line's");
    }
    times.push_back(t);
  });
  if (times.empty()) throw InputError(path.string(), "no times");
  return times;
}

PoseFile read_pose_file(const fs::path& path) {
  std::istringstream in(read_text_file(path, "pose file"));
  io::skip_byte_order_mark(in);
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!skipped(line)) break;
  }
  if (skipped(line)) throw InputError(path.string(), "empty file");
  PoseFile file;
  if (line.find(',') != std::string::npos) {
    const auto fields = split_on(line, ',');
    if (fields.front() == "index") {
      file.kind = PoseFileKind::index_csv;
      file.per_frame = read_odometry_csv(path);
    } else if (is_time_name(fields.front())) {
      file.kind = PoseFileKind::timestamped_csv;
      file.timed = read_timestamped_csv(path);
    } else {
      throw InputError(where(path, line_no),
                       "a CSV pose file starts with a header `index,x,y,theta`, `index,dx,dy,dtheta` or "
                       "`timestamp,x,y,yaw`");
    }
    return file;
  }
  const auto fields = split_on(line, ' ');
  if (fields.size() == 8) {
    file.kind = PoseFileKind::tum;
    file.timed = read_tum(path);
  } else if (fields.size() == 12) {
    file.kind = PoseFileKind::kitti;
    file.per_frame = read_kitti_poses(path);
  } else {
    throw InputError(where(path, line_no),
                     "not a pose file: expected a CSV header, 8 numbers per line (TUM) or 12 "
                     "(KITTI), found " +
                         std::to_string(fields.size()) + " fields");
  }
  return file;
}

std::string tum_text(std::span<const Pose2> poses, std::span<const double> times) {
  if (times.size() != poses.size()) throw std::invalid_argument("tum_text: one time per pose expected");
  std::string text = "# timestamp tx ty tz qx qy qz qw\n";
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const auto& p = poses[k];
    text += fmt::format("{:.9g} {:.9g} {:.9g} 0 0 0 {:.9g} {:.9g}\n", times[k], p.x, p.y, std::sin(p.theta / 2),
                        std::cos(p.theta / 2));
  }
  return text;
}

std::string kitti_text(std::span<const Pose2> poses) {
  // Planar (x, y, theta) is the camera's (tz, -tx) and a turn of -theta about its y axis (down).
  std::string text;
  for (const auto& p : poses) {
    const double c = std::cos(p.theta), s = std::sin(p.theta);
    text += fmt::format("{:.9g} 0 {:.9g} {:.9g} 0 1 0 0 {:.9g} 0 {:.9g} {:.9g}\n", c, 0.0 - s, 0.0 - p.y, s, c, p.x);
  }
  return text;
}

}  // namespace seqtopo::formats
