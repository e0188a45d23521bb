#include "seqtopo/trajectory/pose_graph.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

namespace seqtopo::trajectory {
namespace {

double value_of(double v) { return v; }
template <typename T, int N>
double value_of(const ceres::Jet<T, N>& v) {
  return value_of(v.a);
}

// wrap_angle for automatic differentiation: the shift by 2*pi*k is a constant, so derivatives pass through.
template <typename T>
T wrap(const T& a) {
  constexpr double two_pi = 2.0 * std::numbers::pi;
  return a - T(two_pi * std::floor((value_of(a) + std::numbers::pi) / two_pi));
}

// Odometry edge: the measured motion between consecutive images against between(a, b) of the estimate.
struct OdometryResidual {
  Pose2 measured;
  double sigma_xy, sigma_theta;  // [m], [rad]

  template <typename T>
  bool operator()(const T* a, const T* b, T* r) const {
    using std::cos;
    using std::sin;
    const T c = cos(a[2]), s = sin(a[2]);
    const T dx = b[0] - a[0], dy = b[1] - a[1];
    r[0] = (c * dx + s * dy - measured.x) / sigma_xy;
    r[1] = (-s * dx + c * dy - measured.y) / sigma_xy;
    r[2] = wrap(b[2] - a[2] - measured.theta) / sigma_theta;
    return true;
  }
};

// "Same place" edge: the two positions coincide; headings are left free (the images may face either way).
struct SamePlaceResidual {
  double sigma_xy;  // [m]

  template <typename T>
  bool operator()(const T* a, const T* b, T* r) const {
    r[0] = (a[0] - b[0]) / sigma_xy;
    r[1] = (a[1] - b[1]) / sigma_xy;
    return true;
  }
};

void check_config(const PoseGraphConfig& c) {
  auto check = [](double v, bool allow_zero, const char* name) {
    if (!std::isfinite(v) || v < 0 || (!allow_zero && v == 0)) {
      throw std::invalid_argument(std::string("pose graph: ") + name +
                                  (allow_zero ? " must be finite and >= 0" : " must be finite and > 0"));
    }
  };
  check(c.odometry_sigma_xy, true, "odometry_sigma_xy");
  check(c.odometry_sigma_theta, true, "odometry_sigma_theta");
  check(c.min_sigma_xy, false, "min_sigma_xy");
  check(c.min_sigma_theta, false, "min_sigma_theta");
  check(c.loop_sigma_xy, false, "loop_sigma_xy");
  check(c.loss_scale, false, "loss_scale");
  if (c.max_iterations < 0) throw std::invalid_argument("pose graph: max_iterations must be >= 0");
}

std::unique_ptr<ceres::LossFunction> make_loss(const PoseGraphConfig& c) {
  if (c.loss == "cauchy") return std::make_unique<ceres::CauchyLoss>(c.loss_scale);
  if (c.loss == "huber") return std::make_unique<ceres::HuberLoss>(c.loss_scale);
  if (c.loss == "none") return nullptr;
  throw std::invalid_argument("pose graph: unknown loss '" + c.loss + "' (expected cauchy, huber or none)");
}

}  // namespace

std::vector<Pose2> pose_graph(const std::vector<Pose2>& odometry,
                              const std::vector<std::pair<std::size_t, std::size_t>>& loop_pairs,
                              const PoseGraphConfig& config) {
  check_config(config);
  const std::size_t n = odometry.size();
  for (const auto& [i, j] : loop_pairs) {
    if (i >= n || j >= n) {
      throw std::invalid_argument("pose graph: loop pair (" + std::to_string(i) + ", " + std::to_string(j) +
                                  ") out of range for " + std::to_string(n) + " images");
    }
  }
  std::unique_ptr<ceres::LossFunction> loss = make_loss(config);
  if (n < 2) return odometry;

  std::vector<std::array<double, 3>> poses(n);
  for (std::size_t i = 0; i < n; ++i) poses[i] = {odometry[i].x, odometry[i].y, odometry[i].theta};

  ceres::Problem::Options problem_options;
  // One loss object serves every loop edge, so the problem must not delete it once per edge.
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  for (std::size_t i = 1; i < n; ++i) {
    const Pose2 u = between(odometry[i - 1], odometry[i]);
    const double d = std::hypot(u.x, u.y);
    const double sxy = std::max(config.min_sigma_xy, config.odometry_sigma_xy * d);
    const double sth = std::max(config.min_sigma_theta, config.odometry_sigma_theta * d);
    auto* cost = new ceres::AutoDiffCostFunction<OdometryResidual, 3, 3, 3>(new OdometryResidual{u, sxy, sth});
    problem.AddResidualBlock(cost, nullptr, poses[i - 1].data(), poses[i].data());
  }
  for (const auto& [i, j] : loop_pairs) {
    if (i == j) continue;
    auto* cost =
        new ceres::AutoDiffCostFunction<SamePlaceResidual, 2, 3, 3>(new SamePlaceResidual{config.loop_sigma_xy});
    problem.AddResidualBlock(cost, loss.get(), poses[i].data(), poses[j].data());
  }
  // The graph only knows relative motion: pin the first pose so the map keeps the odometry frame.
  problem.SetParameterBlockConstant(poses[0].data());

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = config.max_iterations;
  options.num_threads = static_cast<int>(std::max(1U, config.threads));
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  // A failed solve (e.g. a numerical breakdown) must not replace the map with garbage: keep the odometry.
  if (!summary.IsSolutionUsable()) return odometry;

  std::vector<Pose2> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = {poses[i][0], poses[i][1], wrap_angle(poses[i][2])};
  return out;
}

}  // namespace seqtopo::trajectory
