#pragma once
// Joint tracking controller at the sample rate: PID on the encoder readings (as on the rig).
// The derivative uses the reference velocity and a first-order low-pass filtered backward
// difference of the measured angle: u = kp e + ki int(e) + kd (qd_ref - qd_est).
#include "exoid/sim/trajectory.hpp"

#include <Eigen/Core>

#include <array>

namespace exoid::sim {

struct PidGains {
  Eigen::Vector2d kp_Nm_per_rad{4.0e4, 1.5e4};   ///< hip, knee; >= 0
  Eigen::Vector2d ki_Nm_per_rad_s{4.0e5, 1.5e5};  ///< >= 0
  Eigen::Vector2d kd_Nms_per_rad{800.0, 150.0};  ///< >= 0
  /// Cutoff of the velocity-estimate filter (Hz); 0 = unfiltered backward difference.
  double derivative_cutoff_Hz = 200.0;
  /// Anti-windup: |integral term| <= this (N m), > 0.
  double integral_limit_Nm = 500.0;
  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

class PidController {
 public:
  PidController(const PidGains& g, double dt_s);
  /// Starts from rest at the measured angles; `enabled[j] = false` makes joint j output 0
  /// (a locked hip). `integral0_Nm` preloads the integral term (e.g. the static holding torque
  /// of the initial pose, as if the controller had been holding the leg before the record).
  void reset(const Eigen::Vector2d& q_meas, const std::array<bool, 2>& enabled,
             const Eigen::Vector2d& integral0_Nm = Eigen::Vector2d::Zero());
  /// Torque command (N m). Allocation-free.
  Eigen::Vector2d update(const JointReference& ref, const Eigen::Vector2d& q_meas);

 private:
  PidGains g_;
  double dt_, alpha_;
  Eigen::Vector2d q_prev_, v_est_, integral_;
  std::array<bool, 2> enabled_{true, true};
};

}  // namespace exoid::sim
