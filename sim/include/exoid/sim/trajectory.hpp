#pragma once
// Joint reference trajectories: the paper's Table 1 and finite Fourier series, with analytic
// derivatives and a smooth start.
//
// Series: q(t) = offset + sum_k a_k cos(2 pi k f0 t) + b_k sin(2 pi k f0 t), k = 1..n.
// Start ramp (duration T): q_ref(t) = q(0) + s(t/T) (q(t) - q(0)), s(x) = 10x^3 - 15x^4 + 6x^5
// (quintic smoothstep, s' = s'' = 0 at both ends), so the leg starts at rest at q(0) with zero
// acceleration and reaches the plain series at t = T, continuous up to qdd.
#include <Eigen/Core>

#include <vector>

namespace exoid::sim {

struct FourierJoint {
  double offset_rad = 0.0;
  std::vector<double> a_rad;  ///< cosine coefficients, harmonic 1..n
  std::vector<double> b_rad;  ///< sine coefficients, harmonic 1..n
};

struct FourierSpec {
  double base_frequency_Hz = 1.0;  ///< f0 > 0
  FourierJoint hip, knee;
  /// Hip held by an equality constraint at hip.offset_rad (the rig's fixed hip); the hip's
  /// harmonics must then be zero.
  bool lock_hip = false;
  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

/// Paper Table 1 (degrees there, radians here), id 1..4:
/// 1: hip -10 (fixed), knee 45 - 30 sin(2 pi t); 2: hip -10 (fixed), knee 60 - 30 sin;
/// 3: hip -30 - 30 sin, knee 75 - 30 sin; 4: hip -45 - 30 sin, knee 60 + 30 sin.
/// Throws std::invalid_argument otherwise.
FourierSpec paperTrajectory(int id);

struct JointReference {
  Eigen::Vector2d q = Eigen::Vector2d::Zero();    ///< rad (hip, knee)
  Eigen::Vector2d qd = Eigen::Vector2d::Zero();   ///< rad/s
  Eigen::Vector2d qdd = Eigen::Vector2d::Zero();  ///< rad/s^2
};

class Trajectory {
 public:
  /// ramp_s >= 0 (0 = no ramp: starts with the series' own velocity).
  Trajectory(FourierSpec spec, double ramp_s);
  /// Reference at time t (allocation-free).
  JointReference at(double t_s) const;
  bool hipLocked() const { return spec_.lock_hip; }
  const FourierSpec& spec() const { return spec_; }
  double ramp_s() const { return ramp_s_; }

 private:
  void raw(double t_s, JointReference& out) const;
  FourierSpec spec_;
  double ramp_s_;
  Eigen::Vector2d q0_;
};

}  // namespace exoid::sim
