#include "seqtopo/mapping/odometry_gate.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace seqtopo::mapping {
namespace {

void check_gate(const OdometryGate& gate) {
  const auto bad = [](double v) { return std::isnan(v) || v < 0; };
  if (bad(gate.base) || bad(gate.drift) || bad(gate.min_consistent) || gate.min_consistent > 1 ||
      bad(gate.trim_window) || bad(gate.trim_floor) || bad(gate.turn)) {
    throw std::invalid_argument(
        "odometry gate: base, drift, trim_window, trim_floor and turn must be >= 0, min_consistent in [0, 1]");
  }
}

void check_pairs(const align::LocalAlignment& alignment, std::size_t poses) {
  for (const auto& [i, j] : alignment.pairs) {
    if (i >= poses || j >= poses) {
      throw std::invalid_argument("alignment pair (" + std::to_string(i) + ", " + std::to_string(j) +
                                  ") is past the odometry's " + std::to_string(poses) + " poses");
    }
  }
}

// travelled[k]: path length of the odometry from image 0 to image k.
std::vector<double> travelled_distance(std::span<const Pose2> odometry) {
  std::vector<double> travelled(odometry.size(), 0.0);
  for (std::size_t k = 1; k < odometry.size(); ++k) {
    travelled[k] = travelled[k - 1] + std::hypot(odometry[k].x - odometry[k - 1].x, odometry[k].y - odometry[k - 1].y);
  }
  return travelled;
}

// The rigid motion (rotation c, s; translation tx, ty) that best superposes the j-side of pairs [lo, hi] on
// their i-side, in least squares (2-D Procrustes).
struct Rigid {
  double c = 1, s = 0, tx = 0, ty = 0;
  bool defined = false;  // false: the j-side points coincide, no rotation is determined
  double spread = 0;     // rms distance of the j-side points from their centre
  double residual(const Pose2& a, const Pose2& b) const {
    return std::hypot(a.x - (c * b.x - s * b.y + tx), a.y - (s * b.x + c * b.y + ty));
  }
};

Rigid superpose(const align::LocalAlignment& alignment, std::span<const Pose2> odometry, std::size_t lo,
                std::size_t hi) {
  double ax = 0, ay = 0, bx = 0, by = 0;
  const auto count = static_cast<double>(hi - lo + 1);
  for (std::size_t k = lo; k <= hi; ++k) {
    const auto& [i, j] = alignment.pairs[k];
    ax += odometry[i].x, ay += odometry[i].y, bx += odometry[j].x, by += odometry[j].y;
  }
  ax /= count, ay /= count, bx /= count, by /= count;
  double dot = 0, cross = 0, spread = 0;
  for (std::size_t k = lo; k <= hi; ++k) {
    const auto& [i, j] = alignment.pairs[k];
    const double px = odometry[j].x - bx, py = odometry[j].y - by;
    const double qx = odometry[i].x - ax, qy = odometry[i].y - ay;
    dot += px * qx + py * qy;
    cross += px * qy - py * qx;
    spread += px * px + py * py;
  }
  Rigid r;
  r.spread = std::sqrt(spread / count);
  // Below a centimetre of spread the direction of the j-side is noise.
  r.defined = spread > 1e-4 * count && std::hypot(dot, cross) > 0;
  if (r.defined) {
    const double norm = std::hypot(dot, cross);
    r.c = dot / norm, r.s = cross / norm;
  }
  r.tx = ax - (r.c * bx - r.s * by);
  r.ty = ay - (r.s * bx + r.c * by);
  return r;
}

align::LocalAlignment trim_one(const align::LocalAlignment& alignment, std::span<const Pose2> odometry,
                               const std::vector<double>& travelled, const OdometryGate& gate) {
  const auto& pairs = alignment.pairs;
  if (pairs.size() < 3 || gate.trim_window == 0) return alignment;
  const auto at = [&](std::size_t k) { return travelled[pairs[k].first]; };  // increasing in k (i increases)
  // The middle: the pairs within half a window of travel of the middle pair.
  const std::size_t mid = pairs.size() / 2;
  std::size_t lo = mid, hi = mid;
  while (lo > 0 && at(mid) - at(lo - 1) <= gate.trim_window / 2) --lo;
  while (hi + 1 < pairs.size() && at(hi + 1) - at(mid) <= gate.trim_window / 2) ++hi;
  const Rigid middle = superpose(alignment, odometry, lo, hi);
  if (!middle.defined) return alignment;
  double squares = 0;
  for (std::size_t k = lo; k <= hi; ++k) {
    const double r = middle.residual(odometry[pairs[k].first], odometry[pairs[k].second]);
    if (r > gate.base) return alignment;
    squares += r * r;
  }
  // How far the two traversals' shapes may part: three times their scatter about the superposition in the
  // middle (a zig-zagging pass, noisy odometry), within [trim_floor, base].
  const double rms = std::sqrt(squares / static_cast<double>(hi - lo + 1));
  const double tolerance = std::clamp(3 * rms, std::min(gate.trim_floor, gate.base), gate.base);
  // Outwards, each new pair against the last trim_window metres accepted on its side.
  while (hi + 1 < pairs.size()) {
    std::size_t from = hi;
    while (from > lo && at(hi + 1) - at(from - 1) <= gate.trim_window) --from;
    const Rigid fit = superpose(alignment, odometry, from, hi);
    if (fit.defined && fit.residual(odometry[pairs[hi + 1].first], odometry[pairs[hi + 1].second]) > tolerance) break;
    ++hi;
  }
  while (lo > 0) {
    std::size_t to = lo;
    while (to < hi && at(to + 1) - at(lo - 1) <= gate.trim_window) ++to;
    const Rigid fit = superpose(alignment, odometry, lo, to);
    if (fit.defined && fit.residual(odometry[pairs[lo - 1].first], odometry[pairs[lo - 1].second]) > tolerance) break;
    --lo;
  }
  if (lo == 0 && hi + 1 == pairs.size()) return alignment;
  return align::pairs_between(alignment, lo, hi);
}

}  // namespace

// A pair's distance in the odometry and the gate's allowance for it (base + drift x travelled between them).
std::pair<double, double> apart_and_allowed(std::span<const Pose2> odometry, const std::vector<double>& travelled,
                                            const OdometryGate& gate, std::size_t i, std::size_t j) {
  return {std::hypot(odometry[i].x - odometry[j].x, odometry[i].y - odometry[j].y),
          gate.base + gate.drift * std::abs(travelled[i] - travelled[j])};
}

namespace {

// Whether the rotation superposing the alignment's two traversals stays within a right angle plus the heading
// drift over the median travel between its pairs (the header); true when the stretch is too short to tell.
bool turns_consistently(const align::LocalAlignment& alignment, std::span<const Pose2> odometry,
                        const std::vector<double>& travelled, const OdometryGate& gate) {
  constexpr double kLeastSpread = 1.0;  // [m]
  const Rigid whole = superpose(alignment, odometry, 0, alignment.pairs.size() - 1);
  if (!whole.defined || whole.spread < kLeastSpread) return true;
  std::vector<double> between;
  between.reserve(alignment.pairs.size());
  for (const auto& [i, j] : alignment.pairs) between.push_back(std::abs(travelled[i] - travelled[j]));
  const auto mid = between.begin() + static_cast<std::ptrdiff_t>(between.size() / 2);
  std::nth_element(between.begin(), mid, between.end());
  return std::abs(std::atan2(whole.s, whole.c)) <= std::numbers::pi / 2 + gate.turn * *mid;
}

}  // namespace

std::string_view verdict_name(OdometryVerdict verdict) {
  switch (verdict) {
    case OdometryVerdict::consistent:
      return "consistent";
    case OdometryVerdict::apart:
      return "apart";
    case OdometryVerdict::turned:
      return "turned";
  }
  return "consistent";
}

std::vector<OdometryVerdict> odometry_verdicts(const std::vector<align::LocalAlignment>& alignments,
                                               std::span<const Pose2> odometry, const OdometryGate& gate) {
  check_gate(gate);
  const std::vector<double> travelled = travelled_distance(odometry);
  std::vector<OdometryVerdict> out;
  out.reserve(alignments.size());
  for (const auto& alignment : alignments) {
    check_pairs(alignment, odometry.size());
    std::size_t consistent = 0;
    for (const auto& [i, j] : alignment.pairs) {
      const auto [apart, allowed] = apart_and_allowed(odometry, travelled, gate, i, j);
      consistent += apart <= allowed;
    }
    if (alignment.pairs.empty() ||
        static_cast<double>(consistent) < gate.min_consistent * static_cast<double>(alignment.pairs.size())) {
      out.push_back(OdometryVerdict::apart);
    } else {
      out.push_back(turns_consistently(alignment, odometry, travelled, gate) ? OdometryVerdict::consistent
                                                                             : OdometryVerdict::turned);
    }
  }
  return out;
}

std::vector<bool> consistent_with_odometry(const std::vector<align::LocalAlignment>& alignments,
                                           std::span<const Pose2> odometry, const OdometryGate& gate) {
  std::vector<bool> out;
  for (const OdometryVerdict v : odometry_verdicts(alignments, odometry, gate)) {
    out.push_back(v == OdometryVerdict::consistent);
  }
  return out;
}

std::vector<double> odometry_agreement(const std::vector<align::LocalAlignment>& alignments,
                                       std::span<const Pose2> odometry, const OdometryGate& gate) {
  check_gate(gate);
  const std::vector<double> travelled = travelled_distance(odometry);
  std::vector<double> out;
  out.reserve(alignments.size());
  for (const auto& alignment : alignments) {
    check_pairs(alignment, odometry.size());
    std::vector<double> ratios;
    ratios.reserve(alignment.pairs.size());
    for (const auto& [i, j] : alignment.pairs) {
      const auto [apart, allowed] = apart_and_allowed(odometry, travelled, gate, i, j);
      ratios.push_back(allowed > 0 ? apart / allowed : (apart > 0 ? HUGE_VAL : 0.0));
    }
    if (ratios.empty()) {
      out.push_back(HUGE_VAL);
      continue;
    }
    const auto mid = ratios.begin() + static_cast<std::ptrdiff_t>(ratios.size() / 2);
    std::nth_element(ratios.begin(), mid, ratios.end());
    out.push_back(*mid);
  }
  return out;
}

std::vector<align::LocalAlignment> trim_to_odometry(const std::vector<align::LocalAlignment>& alignments,
                                                    std::span<const Pose2> odometry, const OdometryGate& gate) {
  check_gate(gate);
  const std::vector<double> travelled = travelled_distance(odometry);
  std::vector<align::LocalAlignment> out;
  out.reserve(alignments.size());
  for (const auto& alignment : alignments) {
    check_pairs(alignment, odometry.size());
    out.push_back(trim_one(alignment, odometry, travelled, gate));
  }
  return out;
}

}  // namespace seqtopo::mapping
