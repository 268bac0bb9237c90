#include "exoid/core/pid.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace exoid::core {

void PidGains::validate(const std::vector<std::string>& names) const {
  std::vector<std::string> joints = names;
  for (int j = 0; names.empty() && j < dof(); ++j) joints.push_back(std::to_string(j));
  auto vec = [&](const char* name, const Eigen::VectorXd& v) {
    if (v.size() != static_cast<Eigen::Index>(joints.size())) {
      throw std::invalid_argument(std::string("'") + name + "' needs one gain per joint (" + std::to_string(joints.size()) + "), got " +
                                  std::to_string(v.size()));
    }
    for (Eigen::Index j = 0; j < v.size(); ++j) {
      if (!std::isfinite(v[j]) || v[j] < 0) {
        std::ostringstream ss;
        ss.precision(17);
        ss << "'" << name << "[" << joints[static_cast<std::size_t>(j)] << "]' must be finite and >= 0, got " << v[j];
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
  reset(std::vector<bool>(static_cast<std::size_t>(g.dof()), true));
}

void PidController::reset(const std::vector<bool>& enabled, const Eigen::VectorXd& integral0_Nm) {
  const Eigen::Index n = g_.dof();
  if (static_cast<Eigen::Index>(enabled.size()) != n || (integral0_Nm.size() != 0 && integral0_Nm.size() != n)) {
    throw std::invalid_argument("PidController::reset: one entry per joint expected");
  }
  e_prev_.setZero(n);
  e_dot_est_.setZero(n);
  first_ = true;
  integral_ = integral0_Nm.size() ? Eigen::VectorXd(integral0_Nm.cwiseMax(-g_.integral_limit_Nm).cwiseMin(g_.integral_limit_Nm))
                                  : Eigen::VectorXd::Zero(n);
  enabled_ = enabled;
}

void PidController::update(const Eigen::Ref<const Eigen::VectorXd>& q_ref, const Eigen::Ref<const Eigen::VectorXd>& qd_ref,
                           const Eigen::Ref<const Eigen::VectorXd>& q_meas, const Eigen::Ref<const Eigen::VectorXd>& qd_meas,
                           Eigen::Ref<Eigen::VectorXd> command) {
  const bool measured = g_.derivative == DerivativeSource::kMeasuredVelocity;
  for (Eigen::Index j = 0; j < g_.dof(); ++j) {
    const double e = q_ref[j] - q_meas[j];
    if (measured) {
      e_dot_est_[j] = qd_ref[j] - qd_meas[j];
    } else {
      const double e_dot_raw = first_ ? 0.0 : (e - e_prev_[j]) / dt_;
      e_dot_est_[j] += alpha_ * (e_dot_raw - e_dot_est_[j]);
    }
    e_prev_[j] = e;
    if (!enabled_[static_cast<std::size_t>(j)]) continue;
    integral_[j] += g_.ki_Nm_per_rad_s[j] * e * dt_;
    integral_[j] = std::clamp(integral_[j], -g_.integral_limit_Nm, g_.integral_limit_Nm);
    command[j] += g_.kp_Nm_per_rad[j] * e;
    command[j] += integral_[j];
    command[j] += g_.kd_Nms_per_rad[j] * e_dot_est_[j];
  }
  first_ = false;
}

}  // namespace exoid::core
