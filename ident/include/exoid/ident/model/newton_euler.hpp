#pragma once
// The joint torques of a serial chain, linear in its standard parameters: tau = Y(q, qd, qdd) phi,
// by the recursive Newton-Euler formulation (Atkeson, An and Hollerbach 1986; Khalil and Dombre,
// "Modeling, identification and control of robots", ch. 9).
#include "exoid/ident/model/chain.hpp"

#include <Eigen/Core>

#include <vector>

namespace exoid::ident {

/// Motion of the frame the chain is mounted in, in that frame. A still base reads
/// ChainBaseMotion::still(model): specific force -g.
struct ChainBaseMotion {
  /// a - g of the base frame's origin (what an accelerometer there reads), m/s^2. Every link
  /// feels it as a uniform field, so base acceleration acts through the same parameters as gravity.
  Eigen::Vector3d specific_force_mps2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d omega_radps = Eigen::Vector3d::Zero();     ///< angular velocity
  Eigen::Vector3d alpha_radps2 = Eigen::Vector3d::Zero();    ///< angular acceleration
  static ChainBaseMotion still(const ChainModel& model) { return {-model.gravity_mps2, {0, 0, 0}, {0, 0, 0}}; }
};

/// dof x standardParameterCount() regressor at one state (joint-relative q in rad, qd in rad/s,
/// qdd in rad/s^2). Friction sees the joint's relative qd; armature its relative qdd.
/// Throws std::invalid_argument if a vector's size is not model.dof().
Eigen::MatrixXd chainRegressor(const ChainModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                               const Eigen::VectorXd& qdd, const ChainBaseMotion& base);
/// On a still base under the model's gravity.
Eigen::MatrixXd chainRegressor(const ChainModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                               const Eigen::VectorXd& qdd);

/// The same rows into `out` (dof x standardParameterCount(), already sized), allocating nothing
/// per call once `work` has seen the model: for long logs.
struct ChainRegressorWorkspace;
void chainRegressorInto(const ChainModel& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                        const Eigen::Ref<const Eigen::VectorXd>& qd, const Eigen::Ref<const Eigen::VectorXd>& qdd,
                        const ChainBaseMotion& base, ChainRegressorWorkspace& work, Eigen::Ref<Eigen::MatrixXd> out);

/// tau = Y(q, qd, qdd) phi directly, by the recursive Newton-Euler algorithm (O(dof), where the
/// regressor is O(dof^2)): a model's inverse dynamics for its closed loop, its feedforward and the
/// torque it predicts along a long record. Same conventions and sizes as chainRegressorInto.
void chainInverseDynamicsInto(const ChainModel& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                              const Eigen::Ref<const Eigen::VectorXd>& qd, const Eigen::Ref<const Eigen::VectorXd>& qdd,
                              const ChainBaseMotion& base, const Eigen::Ref<const Eigen::VectorXd>& phi, ChainRegressorWorkspace& work,
                              Eigen::Ref<Eigen::VectorXd> tau);

struct ChainRegressorWorkspace {
  /// Joint i's axis and origin seen from the link being processed (its frame), per joint i.
  std::vector<Eigen::Vector3d> axis_seen, origin_seen;
  std::vector<int> link_column;  ///< first column of each link's parameters
  /// Inverse dynamics: each link's rotation from its parent, offset, and wrench about its origin.
  std::vector<Eigen::Matrix3d> R;
  std::vector<Eigen::Vector3d> force, moment;
};

}  // namespace exoid::ident
