#include "seqtopo/trajectory/ekf_map.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace seqtopo::trajectory {
namespace {

void check_config(const EkfConfig& c) {
  auto non_negative = [](double v, const char* name) {
    if (!std::isfinite(v) || v < 0)
      throw std::invalid_argument(std::string("EKF: ") + name + " must be finite and >= 0");
  };
  auto positive = [](double v, const char* name) {
    if (!std::isfinite(v) || v <= 0)
      throw std::invalid_argument(std::string("EKF: ") + name + " must be finite and > 0");
  };
  non_negative(c.odometry_sigma_xy_per_m, "odometry_sigma_xy_per_m");
  non_negative(c.odometry_sigma_theta_per_m, "odometry_sigma_theta_per_m");
  // Positive floors keep the process noise positive definite even for a robot standing still.
  positive(c.min_sigma_xy, "min_sigma_xy");
  positive(c.min_sigma_theta, "min_sigma_theta");
  positive(c.observation_sigma, "observation_sigma");
}

void symmetrise(Eigen::MatrixXd& P, Eigen::Index n) {
  const Eigen::MatrixXd upper_from_lower = P.topLeftCorner(n, n).transpose();
  P.topLeftCorner(n, n) = 0.5 * (P.topLeftCorner(n, n) + upper_from_lower);
}

}  // namespace

EkfResult ekf_map(const std::vector<Pose2>& odometry, const std::vector<int>& labels, const EkfConfig& config) {
  if (odometry.size() != labels.size()) {
    throw std::invalid_argument("EKF: " + std::to_string(odometry.size()) + " odometry poses but " +
                                std::to_string(labels.size()) + " labels");
  }
  check_config(config);
  EkfResult result;
  if (odometry.empty()) return result;

  // State: robot (x, y, theta) then one (x, y) per place in order of first sighting. The full size is
  // known up front, so the covariance is allocated once and only its active corner is used.
  std::unordered_map<int, Eigen::Index> offset_of;
  Eigen::Index full = 3;
  for (int label : labels) {
    if (label >= 0 && offset_of.emplace(label, full).second) full += 2;
  }
  offset_of.clear();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(full);
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(full, full);
  Eigen::Index n = 3;  // active state size
  x.head<3>() << odometry[0].x, odometry[0].y, odometry[0].theta;
  const double r = config.observation_sigma * config.observation_sigma;  // [m^2]

  std::size_t updates = 0;
  result.robot.reserve(odometry.size());
  for (std::size_t i = 0; i < odometry.size(); ++i) {
    if (i > 0) {
      // Prediction from odometry alone: x_r <- x_r (+) u, only the robot rows and columns change.
      const Pose2 u = between(odometry[i - 1], odometry[i]);
      const double c = std::cos(x(2)), s = std::sin(x(2));
      Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
      F(0, 2) = -s * u.x - c * u.y;
      F(1, 2) = c * u.x - s * u.y;
      Eigen::Matrix3d G = Eigen::Matrix3d::Identity();
      G.topLeftCorner<2, 2>() << c, -s, s, c;
      const double d = std::hypot(u.x, u.y);
      const double sxy = std::max(config.min_sigma_xy, config.odometry_sigma_xy_per_m * d);
      const double sth = std::max(config.min_sigma_theta, config.odometry_sigma_theta_per_m * d);
      const Eigen::Vector3d q(sxy * sxy, sxy * sxy, sth * sth);
      const Pose2 predicted = compose({x(0), x(1), x(2)}, u);
      x.head<3>() << predicted.x, predicted.y, predicted.theta;
      const Eigen::Matrix3d Prr = P.topLeftCorner<3, 3>();
      P.topLeftCorner<3, 3>() = F * Prr * F.transpose() + G * q.asDiagonal() * G.transpose();
      if (n > 3) {
        const Eigen::MatrixXd Prl = F * P.block(0, 3, 3, n - 3);
        P.block(0, 3, 3, n - 3) = Prl;
        P.block(3, 0, n - 3, 3) = Prl.transpose();
      }
    }

    const int label = labels[i];
    if (label >= 0) {
      const auto [it, first_sighting] = offset_of.emplace(label, n);
      const Eigen::Index o = it->second;
      if (first_sighting) {
        // The place is where the robot stands, give or take one observation error.
        x.segment<2>(o) = x.head<2>();
        P.block(o, 0, 2, n) = P.block(0, 0, 2, n);
        P.block(0, o, n, 2) = P.block(0, 0, n, 2);
        P.block<2, 2>(o, o) = P.topLeftCorner<2, 2>() + r * Eigen::Matrix2d::Identity();
        n += 2;
      } else {
        // Observation h(x) = robot xy - place xy, measured as 0. H has +I on the robot's xy and -I on
        // the place's, so P H^T is a difference of two column pairs (no n x n products).
        const Eigen::MatrixXd PHt = P.block(0, 0, n, 2) - P.block(0, o, n, 2);
        const Eigen::Matrix2d S = PHt.topRows<2>() - PHt.middleRows<2>(o) + r * Eigen::Matrix2d::Identity();
        const Eigen::Vector2d innovation = -(x.head<2>() - x.segment<2>(o));
        const Eigen::MatrixXd K = PHt * S.inverse();
        x.head(n) += K * innovation;
        x(2) = wrap_angle(x(2));
        P.topLeftCorner(n, n).noalias() -= K * PHt.transpose();
        // Rounding makes P drift from symmetric over many updates; re-symmetrising after each one would
        // double the O(n^2) memory traffic that dominates the run time, so it is done now and then.
        if (++updates % 32 == 0) symmetrise(P, n);
      }
    }
    result.robot.push_back({x(0), x(1), x(2)});
  }

  for (const auto& [label, o] : offset_of) result.landmarks[label] = {x(o), x(o + 1)};
  result.images = result.robot;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (labels[i] < 0) continue;
    const auto& p = result.landmarks.at(labels[i]);
    result.images[i].x = p[0];
    result.images[i].y = p[1];
  }
  return result;
}

}  // namespace seqtopo::trajectory
