#pragma once
// The one trajectory type of the simulator, the identification and the excitation design: per
// joint a periodic finite Fourier series,
//   q_j(t) = offset_j + sum_{k=1..N} a_kj cos(k w t) + b_kj sin(k w t),  w = 2 pi f0,
// with analytic velocity and acceleration. The first `locked_joints` joints are held at their
// offsets by the rig's lock (the APAL leg's hip in the paper's knee-only trajectories, a chain's
// proximal joints in a segmental stage): their harmonics are zero.
#include <Eigen/Core>

namespace exoid::core {

struct FourierSeries {
  double f0_hz = 0.1;             ///< base frequency, > 0; the period is 1 / f0
  Eigen::VectorXd offset_rad;     ///< one per joint
  Eigen::MatrixXd a_rad, b_rad;   ///< harmonics x joints (harmonic k in row k - 1): cosine, sine
  int locked_joints = 0;          ///< the first joints held at their offsets, [0, dof]

  /// Zero harmonics of `dof` joints at rest at `offset_rad` (0 when not given).
  static FourierSeries still(int dof, int harmonics, double f0_hz);
  int dof() const { return static_cast<int>(offset_rad.size()); }
  int harmonics() const { return static_cast<int>(a_rad.rows()); }
  double period_s() const { return 1.0 / f0_hz; }
  /// q, qd, qdd at t (rad, rad/s, rad/s^2), sized dof() (Eigen::VectorXd, or a fixed-size
  /// vector of dof() entries).
  template <typename Vector>
  void at(double t_s, Vector& q, Vector& qd, Vector& qdd) const {
    q = offset_rad;
    qd.setZero(dof());
    qdd.setZero(dof());
    addHarmonics(t_s, q, qd, qdd);
  }
  /// Harmonic k (1-based) at angular frequency w, where cos(w t) = c and sin(w t) = s, added to
  /// q, qd, qdd: the one expression at() and a design's precomputed period grid share, so both
  /// give the same bits.
  void addHarmonic(int k, double w, double c, double s, Eigen::Ref<Eigen::VectorXd> q, Eigen::Ref<Eigen::VectorXd> qd,
                   Eigen::Ref<Eigen::VectorXd> qdd) const;
  /// Every harmonic at t added to q, qd, qdd (what at() adds to the offsets).
  void addHarmonics(double t_s, Eigen::Ref<Eigen::VectorXd> q, Eigen::Ref<Eigen::VectorXd> qd, Eigen::Ref<Eigen::VectorXd> qdd) const;
  /// Throws std::invalid_argument naming the field: f0 <= 0, sizes, a NaN or Inf, a locked joint
  /// that moves.
  void validate() const;
};

}  // namespace exoid::core
