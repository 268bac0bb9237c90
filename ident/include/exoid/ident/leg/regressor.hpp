#pragma once
// The corrected 2-link regressor: [T_hip; T_knee] = Y(q, qd, qdd) X (paper.md, "Regressor").
#include "exoid/ident/leg/params.hpp"
#include "exoid/ident/signals/joint_signals.hpp"

#include <Eigen/Core>

namespace exoid::ident {

/// Constants the regressor needs besides X: the thigh length Lt and gravity.
struct LegConstants {
  double thigh_length_m = 0.45;  ///< Lt, hip to knee axis. A 1 cm error biases thigh params ~20 %.
  double gravity_mps2 = 9.81;    ///< g
  /// Throws std::invalid_argument unless both are finite and positive.
  void validate() const;
};

enum class Joint : int { kHip = 0, kKnee = 1 };

using RegressorRow = Eigen::Matrix<double, 1, kNumParams>;

/// sgn with sgn(0) = 0, as in the paper's friction model.
inline double sgn(double v) { return (v > 0.0) - (v < 0.0); }

/// Both regressor rows at one state. q = (hip, knee) in rad, qd in rad/s, qdd in rad/s^2.
void regressorRows(const LegConstants& c, const Eigen::Vector2d& q, const Eigen::Vector2d& qd,
                   const Eigen::Vector2d& qdd, RegressorRow& hip, RegressorRow& knee);

/// Motion of the frame the hip is mounted in (the pedestal, pitching about an axis parallel to
/// the joints), as an IMU at the hip axis reads it in that frame.
struct BaseMotion {
  /// Specific force at the hip axis in the base frame (x anterior, z up): a - g, so a still base
  /// reads (0, +g). Every link mass feels -f as a uniform field: base acceleration acts exactly
  /// like gravity, through the same parameters.
  double f_x_mps2 = 0.0, f_z_mps2 = 0.0;
  /// Base pitch rate and acceleration about the joint axes (same sign as q): the links' absolute
  /// angular rates are qd1 + omega, accelerations qdd1 + alpha. Friction sees the relative qd.
  double omega_radps = 0.0, alpha_radps2 = 0.0;
  static BaseMotion still(double g) { return {0.0, g, 0.0, 0.0}; }
};

/// The rows on a moving base: the same 10 parameters, no new unknowns. The gravity terms
/// g sin(th), g cos(th) of each link (th = q1, q1 + q2) become f_z sin(th) - f_x cos(th) and
/// f_z cos(th) + f_x sin(th); the inertial terms use the absolute rates. With
/// BaseMotion::still(c.gravity_mps2) this is regressorRows above.
void regressorRows(const LegConstants& c, const Eigen::Vector2d& q, const Eigen::Vector2d& qd,
                   const Eigen::Vector2d& qdd, const BaseMotion& base, RegressorRow& hip, RegressorRow& knee);

/// N x 10 regressor of one joint's equation over a record.
Eigen::MatrixXd jointRegressor(const JointSignals& s, Joint joint, const LegConstants& c);
/// The regressor columns that are not zero by construction, N x 13: the hip's first 8 (Mxt .. Js;
/// its equation has no knee friction) then the knee's last 5 (Mxs .. fv2; no thigh parameter). The
/// same values as jointRegressor's in those columns, in 13/20 of the memory.
constexpr int kHipColumns = 8, kKneeFirstColumn = 5;
void nonzeroRegressorColumns(const JointSignals& s, const LegConstants& c, Eigen::Ref<Eigen::MatrixXd> out);
/// 2N x 10, both equations in time order: row 2i is sample i's hip row, 2i+1 its knee row
/// (so RLS over the rows sees the record in time order). Matches stackedTorque().
Eigen::MatrixXd stackedRegressor(const JointSignals& s, const LegConstants& c);
/// 2N: [tau_hip_0, tau_knee_0, tau_hip_1, ...].
Eigen::VectorXd stackedTorque(const JointSignals& s);
/// N x 2 torques predicted by X along a record.
Eigen::MatrixX2d predictTorque(const JointSignals& s, const ParamVector& x, const LegConstants& c);

}  // namespace exoid::ident
