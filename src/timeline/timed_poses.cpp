#include "seqtopo/timeline/timed_poses.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace seqtopo::timeline {
namespace {

std::string seconds(double t) {
  char text[64];
  std::snprintf(text, sizeof text, "%.3f", t);
  return text;
}

bool finite(const Pose2& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.theta); }

Pose2 between_poses(const TimedPose& a, const TimedPose& b, double t) {
  const double u = (t - a.time) / (b.time - a.time);
  const double turn = wrap_angle(b.pose.theta - a.pose.theta);
  return {a.pose.x + u * (b.pose.x - a.pose.x), a.pose.y + u * (b.pose.y - a.pose.y),
          wrap_angle(a.pose.theta + u * turn)};
}

}  // namespace

void check_increasing(std::span<const double> times) {
  for (std::size_t k = 0; k < times.size(); ++k) {
    if (!std::isfinite(times[k])) throw std::invalid_argument("time " + std::to_string(k) + " is not finite");
    if (k > 0 && !(times[k] > times[k - 1])) {
      throw std::invalid_argument("times must increase: " + std::to_string(k) + " (" + seconds(times[k]) +
                                  " s) does not come after " + std::to_string(k - 1) + " (" + seconds(times[k - 1]) +
                                  " s)");
    }
  }
}

InterpolatedPoses interpolate_poses(std::span<const TimedPose> poses, std::span<const double> times,
                                    const InterpolationConfig& config) {
  if (poses.empty()) throw std::invalid_argument("no poses to interpolate");
  if (!(config.max_extrapolation >= 0)) throw std::invalid_argument("max_extrapolation must be >= 0");
  for (std::size_t k = 0; k < poses.size(); ++k) {
    if (!std::isfinite(poses[k].time) || !finite(poses[k].pose))
      throw std::invalid_argument("pose " + std::to_string(k) + " is not finite");
    if (k > 0 && !(poses[k].time > poses[k - 1].time)) {
      throw std::invalid_argument("pose times must increase: pose " + std::to_string(k) + " at " +
                                  seconds(poses[k].time) + " s does not come after " + seconds(poses[k - 1].time) +
                                  " s");
    }
  }
  for (std::size_t k = 0; k < times.size(); ++k) {
    if (!std::isfinite(times[k])) throw std::invalid_argument("image time " + std::to_string(k) + " is not finite");
  }
  const double first = poses.front().time, last = poses.back().time;
  if (!times.empty()) {
    const auto [lo, hi] = std::minmax_element(times.begin(), times.end());
    if (*hi < first - config.max_extrapolation || *lo > last + config.max_extrapolation) {
      throw std::invalid_argument("the time ranges do not overlap: images " + seconds(*lo) + " .. " + seconds(*hi) +
                                  " s, poses " + seconds(first) + " .. " + seconds(last) + " s");
    }
  }
  InterpolatedPoses out;
  out.poses.reserve(times.size());
  std::size_t outside = 0, first_outside = 0;
  for (std::size_t k = 0; k < times.size(); ++k) {
    const double t = times[k];
    if (t < first || t > last) {
      if (t < first - config.max_extrapolation || t > last + config.max_extrapolation) {
        if (outside++ == 0) first_outside = k;
        continue;
      }
      out.poses.push_back(t < first ? poses.front().pose : poses.back().pose);
      ++out.held_at_end;
      continue;
    }
    // The first pose at or after t.
    const auto it = std::lower_bound(poses.begin(), poses.end(), t,
                                     [](const TimedPose& p, double value) { return p.time < value; });
    if (it->time == t) {
      out.poses.push_back(it->pose);
    } else {
      out.poses.push_back(between_poses(*(it - 1), *it, t));
    }
  }
  if (outside > 0) {
    throw std::invalid_argument(std::to_string(outside) + " of " + std::to_string(times.size()) +
                                " images lie more than " + seconds(config.max_extrapolation) +
                                " s outside the poses' time range " + seconds(first) + " .. " + seconds(last) +
                                " s (the first: image " + std::to_string(first_outside) + " at " +
                                seconds(times[first_outside]) + " s)");
  }
  return out;
}

std::vector<std::size_t> select_every_metres(std::span<const Pose2> poses, double metres) {
  if (!(metres > 0) || !std::isfinite(metres)) throw std::invalid_argument("metres must be a finite number > 0");
  std::vector<std::size_t> kept;
  if (poses.empty()) return kept;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    if (!finite(poses[k])) throw std::invalid_argument("pose " + std::to_string(k) + " is not finite");
  }
  kept.push_back(0);
  // Marks at D, 2D, 3D, ... of path length: the first frame at or past each mark is kept (a step that passes
  // several marks keeps one frame), so the spacing is D on average, not D plus each frame's overshoot.
  double travelled = 0;  // [m] path length from frame 0
  double mark = metres;
  for (std::size_t k = 1; k < poses.size(); ++k) {
    travelled += std::hypot(poses[k].x - poses[k - 1].x, poses[k].y - poses[k - 1].y);
    if (travelled >= mark) {
      kept.push_back(k);
      mark = (std::floor(travelled / metres) + 1) * metres;
    }
  }
  return kept;
}

}  // namespace seqtopo::timeline
