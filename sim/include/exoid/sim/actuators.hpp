#pragma once
// What lies between the controller's torque command and the torque a joint gets. The hip is a
// geared electric motor under current control, the knee a hydraulic servo valve and cylinder
// acting through the four-bar; each is a second-order low-pass from command to joint torque
// (SecondOrderLowpass). Values and sources: models/README.md ("Actuators").
#include "exoid/sim/lowpass.hpp"

#include <Eigen/Core>

#include <array>

namespace exoid::sim {

struct ActuatorOptions {
  /// Hip motor torque bandwidth (Hz, -3 dB with damping 1/sqrt(2)). Default 60 Hz: measured
  /// whole-actuator torque bandwidths of exoskeleton hip drives are 62-66 Hz. 0 = ideal.
  double hip_bandwidth_Hz = 60.0;
  double hip_damping = 0.70710678118654752;
  /// Knee hydraulic force loop bandwidth (Hz). Default 20 Hz: the valve (>= 60 Hz) is faster than
  /// the oil column's resonance, which limits closed-loop force control to ~20 Hz. 0 = ideal.
  double knee_bandwidth_Hz = 20.0;
  double knee_damping = 0.70710678118654752;
  /// Throws std::invalid_argument naming the field (bandwidths in [0, Nyquist), damping > 0).
  void validate(double dt_s) const;
};

/// The two joints' actuators at the sample rate.
class Actuators {
 public:
  Actuators(const ActuatorOptions& o, double dt_s);
  /// Steady state delivering these torques.
  void reset(const Eigen::Vector2d& tau_Nm);
  /// Torques the joints get this sample for the commands (N m). Allocation-free.
  Eigen::Vector2d step(const Eigen::Vector2d& command_Nm);
  /// The command that makes an actuator deliver a torque trajectory: the inverse of its
  /// continuous transfer function, u = tau + (2 zeta / wn) tau' + tau'' / wn^2 (tau', tau'' in
  /// N m/s, N m/s^2). Model-based feedforward uses it to cancel the actuator lag.
  Eigen::Vector2d inverse(const Eigen::Vector2d& tau, const Eigen::Vector2d& tau_dot,
                          const Eigen::Vector2d& tau_ddot) const;

 private:
  std::array<SecondOrderLowpass, 2> lag_;
  Eigen::Vector2d lead1_, lead2_;  // 2 zeta / wn and 1 / wn^2 per joint (0 for an ideal actuator)
};

}  // namespace exoid::sim
