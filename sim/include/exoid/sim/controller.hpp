#pragma once
// Joint tracking controller at the sample rate: PID on the encoder readings (as on the rig).
// e = q_ref - q_meas; the derivative is a first-order low-pass filtered backward difference of
// e itself, so the reference and the measurement see the same filter lag (a lagged velocity
// estimate compared with the exact reference velocity would make the D term fight the
// feedforward): u = kp e + ki int(e) + kd de_est.
#include "exoid/sim/trajectory.hpp"

#include <Eigen/Core>

#include <array>

namespace exoid::sim {

/// Defaults: the feedback of a rig with model-based feedforward, a critically damped position
/// loop at wn = 2 pi 4 Hz on the joint inertias (hip J ~ 3.5 kg m^2, knee ~ 0.6 kg m^2 with the
/// cylinder): kp = J wn^2, kd = 2 J wn, well below the knee's 20 Hz force loop; a slow integral
/// (wi = 2 pi 0.5 Hz) for what the model misses.
struct PidGains {
  Eigen::Vector2d kp_Nm_per_rad{2200.0, 380.0};   ///< hip, knee; >= 0
  Eigen::Vector2d ki_Nm_per_rad_s{6900.0, 1200.0};  ///< >= 0
  Eigen::Vector2d kd_Nms_per_rad{176.0, 30.0};  ///< >= 0
  /// Cutoff of the velocity-estimate filter (Hz); 0 = unfiltered backward difference. 100 Hz:
  /// >10x the position loop, the usual compromise between lag and encoder noise.
  double derivative_cutoff_Hz = 100.0;
  /// Anti-windup: |integral term| <= this (N m), > 0.
  double integral_limit_Nm = 500.0;
  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

class PidController {
 public:
  PidController(const PidGains& g, double dt_s);
  /// Starts from rest (the first sample's error derivative is taken as 0); `enabled[j] = false` makes joint j output 0
  /// (a locked hip). `integral0_Nm` preloads the integral term (e.g. the static holding torque
  /// of the initial pose, as if the controller had been holding the leg before the record).
  void reset(const Eigen::Vector2d& q_meas, const std::array<bool, 2>& enabled,
             const Eigen::Vector2d& integral0_Nm = Eigen::Vector2d::Zero());
  /// Torque command (N m). Allocation-free.
  Eigen::Vector2d update(const JointReference& ref, const Eigen::Vector2d& q_meas);

 private:
  PidGains g_;
  double dt_, alpha_;
  Eigen::Vector2d e_prev_, e_dot_est_, integral_;
  bool first_ = true;
  std::array<bool, 2> enabled_{true, true};
};

}  // namespace exoid::sim
