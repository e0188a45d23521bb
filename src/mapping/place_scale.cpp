#include "seqtopo/mapping/place_scale.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "median.hpp"

namespace seqtopo::mapping {

using detail::median;

PlaceScale estimate_frames_per_place(const align::ScoreSource& s, std::size_t max_lag) {
  const std::size_t n = s.rows();
  if (n == 0 || s.cols() != n) throw std::invalid_argument("frames per place: the similarity must be square");
  const std::size_t lags = std::min(max_lag, n / 3);
  if (lags < 4) return {};
  // by_lag[k]: S(i, i + k) for every sampled i, as read (float); read a row segment at a time.
  const std::size_t stride = (n + kPlaceScaleFrames - 1) / kPlaceScaleFrames;
  const std::size_t sampled = (n + stride - 1) / stride;
  std::vector<std::vector<align::Score>> by_lag(lags + 1);
  for (auto& v : by_lag) v.reserve(sampled);
  std::vector<align::Score> row(lags + 1);
  for (std::size_t i = 0; i < n; i += stride) {
    const std::size_t end = std::min(n, i + lags + 1);
    s.read_row(i, i, end, row.data());
    for (std::size_t k = 0; k < end - i; ++k) by_lag[k].push_back(row[k]);
  }
  return frames_per_place_from_lags(std::move(by_lag), n);
}

PlaceScale frames_per_place_from_lags(std::vector<std::vector<float>> by_lag, std::size_t n) {
  if (by_lag.size() < 5) return {};
  const std::size_t lags = by_lag.size() - 1;
  for (const auto& v : by_lag) {
    if (v.empty()) return {};
  }
  std::vector<double> c(lags + 1);
  for (std::size_t k = 0; k <= lags; ++k) c[k] = median(std::move(by_lag[k]));
  const double far = median(std::vector<double>(c.begin() + static_cast<std::ptrdiff_t>(lags / 2), c.end()));
  const double peak = c[0] - far;
  if (!(peak > 0)) return {};
  // No flat background: the similarity drifts at every scale.
  if (c[lags / 2] - c[lags] > 0.2 * (c[0] - c[lags])) return {};
  const double target = 0.5;  // the half-life
  for (std::size_t k = 1; k <= lags; ++k) {
    const double rel = (c[k] - far) / peak;
    if (rel < target) {
      const double prev = (c[k - 1] - far) / peak;
      const double lag = static_cast<double>(k - 1) + (prev - target) / (prev - rel);
      // A sequence holds at least 50 places: a longer estimate is the descriptors drifting, not a place.
      const double most = std::max(1.0, static_cast<double>(n) / 50.0);
      if (lag > most) return {};
      return {std::max(lag, 1.0), true};
    }
  }
  return {};
}

PlaceScale frames_per_place_from_odometry(std::span<const Pose2> odometry, double place_length) {
  std::vector<double> steps;
  for (std::size_t k = 1; k < odometry.size(); ++k) {
    steps.push_back(std::hypot(odometry[k].x - odometry[k - 1].x, odometry[k].y - odometry[k - 1].y));
  }
  const double step = median(std::move(steps));
  if (!(step > 0) || !std::isfinite(step)) return {};
  return {std::max(1.0, place_length / step), true};
}

PlaceScale place_scale(std::span<const Pose2> odometry, const std::function<PlaceScale()>& from_similarity) {
  if (!odometry.empty()) {
    const PlaceScale travelled = frames_per_place_from_odometry(odometry);
    if (travelled.found) return travelled;
  }
  return from_similarity();
}

}  // namespace seqtopo::mapping
