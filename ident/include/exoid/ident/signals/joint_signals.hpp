#pragma once
// A record's joint states as time series, whatever the robot: the rows the regressors are built from.
#include <Eigen/Core>

namespace exoid::ident {

/// Time series of the joints (the APAL leg: column 0 = hip, 1 = knee; a chain: its joints base to
/// tip), SI units. Rows are samples.
struct JointSignals {
  Eigen::VectorXd t_s;
  Eigen::MatrixXd q_rad;
  Eigen::MatrixXd qd_radps;
  Eigen::MatrixXd qdd_radps2;
  Eigen::MatrixXd tau_Nm;
  /// Optional base motion per sample, columns (f_x, f_z, omega, alpha) as in BaseMotion (leg/regressor.hpp): the
  /// planar IMU's specific force x and z, pitch rate and acceleration about y, in the base frame; empty =
  /// a still base under gravity.
  Eigen::Matrix<double, Eigen::Dynamic, 4> base;
  Eigen::Index size() const { return t_s.size(); }
  /// Throws std::invalid_argument if the sizes disagree or a value is not finite.
  void validate() const;
};

}  // namespace exoid::ident
