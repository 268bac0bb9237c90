#include "exoid/sim/controller.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace exoid::sim {

void PidGains::validate() const {
  auto vec = [](const char* name, const Eigen::Vector2d& v) {
    for (int j = 0; j < 2; ++j) {
      if (!std::isfinite(v[j]) || v[j] < 0) {
        std::ostringstream ss;
        ss.precision(17);
        ss << "'" << name << (j == 0 ? "[hip]" : "[knee]") << "' must be finite and >= 0, got " << v[j];
        throw std::invalid_argument(ss.str());
      }
    }
  };
  vec("gains.kp_Nm_per_rad", kp_Nm_per_rad);
  vec("gains.ki_Nm_per_rad_s", ki_Nm_per_rad_s);
  vec("gains.kd_Nms_per_rad", kd_Nms_per_rad);
  if (!std::isfinite(derivative_cutoff_Hz) || derivative_cutoff_Hz < 0) {
    std::ostringstream ss;
    ss << "'gains.derivative_cutoff_Hz' must be >= 0 (0 = unfiltered), got " << derivative_cutoff_Hz;
    throw std::invalid_argument(ss.str());
  }
  if (!std::isfinite(integral_limit_Nm) || integral_limit_Nm <= 0) {
    std::ostringstream ss;
    ss << "'gains.integral_limit_Nm' must be > 0, got " << integral_limit_Nm;
    throw std::invalid_argument(ss.str());
  }
}

PidController::PidController(const PidGains& g, double dt_s) : g_(g), dt_(dt_s) {
  g.validate();
  if (!(dt_s > 0)) throw std::invalid_argument("PidController: dt_s must be > 0");
  // First-order low-pass y += alpha (x - y), alpha = dt / (dt + 1 / (2 pi fc)).
  alpha_ = g.derivative_cutoff_Hz > 0 ? dt_ / (dt_ + 1.0 / (2 * M_PI * g.derivative_cutoff_Hz)) : 1.0;
  reset(Eigen::Vector2d::Zero(), {true, true});
}

void PidController::reset(const Eigen::Vector2d& /*q_meas*/, const std::array<bool, 2>& enabled,
                          const Eigen::Vector2d& integral0_Nm) {
  e_prev_.setZero();
  e_dot_est_.setZero();
  first_ = true;
  integral_ = integral0_Nm.cwiseMax(-g_.integral_limit_Nm).cwiseMin(g_.integral_limit_Nm);
  enabled_ = enabled;
}

Eigen::Vector2d PidController::update(const JointReference& ref, const Eigen::Vector2d& q_meas) {
  Eigen::Vector2d u;
  for (int j = 0; j < 2; ++j) {
    const double e = ref.q[j] - q_meas[j];
    const double e_dot_raw = first_ ? 0.0 : (e - e_prev_[j]) / dt_;
    e_dot_est_[j] += alpha_ * (e_dot_raw - e_dot_est_[j]);
    e_prev_[j] = e;
    if (!enabled_[static_cast<std::size_t>(j)]) {
      u[j] = 0.0;
      continue;
    }
    integral_[j] += g_.ki_Nm_per_rad_s[j] * e * dt_;
    integral_[j] = std::clamp(integral_[j], -g_.integral_limit_Nm, g_.integral_limit_Nm);
    u[j] = g_.kp_Nm_per_rad[j] * e + integral_[j] + g_.kd_Nms_per_rad[j] * e_dot_est_[j];
  }
  first_ = false;
  return u;
}

}  // namespace exoid::sim
