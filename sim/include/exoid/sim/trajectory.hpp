#pragma once
// The APAL leg's joint references: the paper's Table 1 and any finite Fourier series of its two
// joints (core::FourierSeries, the one trajectory type), with a smooth start.
//
// Start ramp (duration T): q_ref(t) = q(0) + s(t/T) (q(t) - q(0)), s(x) = 10x^3 - 15x^4 + 6x^5
// (quintic smoothstep, s' = s'' = 0 at both ends), so the leg starts at rest at q(0) with zero
// acceleration and reaches the plain series at t = T, continuous up to qdd.
#include "exoid/core/fourier_series.hpp"

#include <Eigen/Core>

namespace exoid::sim {

/// Paper Table 1 (degrees there, radians here), id 1..4, hip and knee, 1 Hz:
/// 1: hip -10 (locked), knee 45 - 30 sin(2 pi t); 2: hip -10 (locked), knee 60 - 30 sin;
/// 3: hip -30 - 30 sin, knee 75 - 30 sin; 4: hip -45 - 30 sin, knee 60 + 30 sin.
/// Throws std::invalid_argument otherwise.
core::FourierSeries paperTrajectory(int id);

struct JointReference {
  Eigen::Vector2d q = Eigen::Vector2d::Zero();    ///< rad (hip, knee)
  Eigen::Vector2d qd = Eigen::Vector2d::Zero();   ///< rad/s
  Eigen::Vector2d qdd = Eigen::Vector2d::Zero();  ///< rad/s^2
};

class Trajectory {
 public:
  /// spec: the hip and the knee (the hip locked when spec.locked_joints is 1); ramp_s >= 0 (0 =
  /// no ramp: starts with the series' own velocity). Throws std::invalid_argument naming the field.
  Trajectory(core::FourierSeries spec, double ramp_s);
  /// Reference at time t (allocation-free).
  JointReference at(double t_s) const;
  bool hipLocked() const { return spec_.locked_joints > 0; }
  const core::FourierSeries& spec() const { return spec_; }
  double ramp_s() const { return ramp_s_; }

 private:
  void raw(double t_s, JointReference& out) const { spec_.at(t_s, out.q, out.qd, out.qdd); }
  core::FourierSeries spec_;
  double ramp_s_;
  Eigen::Vector2d q0_;
};

}  // namespace exoid::sim
