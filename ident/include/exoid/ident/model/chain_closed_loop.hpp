#pragma once
// Any serial chain identified in base parameters, simulated under its rig's tracking controller:
// what IDIM-IV needs (chain_idim_iv.hpp) to build instruments that share the motion of a record
// but not its measurement noise. Pure Eigen, as the 2-link leg's (leg/closed_loop.hpp); the
// controller is whatever the user describes, so it serves real logs as well as exoid's chain
// simulator (whose controller it mirrors: sim/chain_simulate.hpp).
#include "exoid/ident/leg/closed_loop.hpp"
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/ident/model/chain.hpp"

#include <Eigen/Core>

namespace exoid::ident {

/// Per joint j: command u_j = ff_j + kp_j (q_ref,j - q_j) + kd_j (qd_ref,j - qd_j), the velocity
/// measured (a tachometer, as the chain rig's), updated once per sample and held; the motor
/// torque follows u through a first-order lag of actuator_bandwidth_hz (0 = at once).
struct ChainController {
  Eigen::VectorXd kp_Nm_per_rad;   ///< one per joint, >= 0
  Eigen::VectorXd kd_Nms_per_rad;  ///< one per joint, >= 0
  /// kModel: the identified model's own inverse dynamics on the reference (the chain rig's:
  /// MuJoCo's inverse dynamics plus its Coulomb term).
  Feedforward feedforward = Feedforward::kModel;
  double actuator_bandwidth_hz = 0.0;  ///< >= 0
  /// Throws std::invalid_argument naming the field: sizes other than dof, a negative or
  /// non-finite gain, no joint with kp > 0.
  void validate(int dof) const;
};

/// The reference the controller tracked, sampled like the record (uniform dt): samples x dof.
using ChainReference = SampledReference<Eigen::MatrixXd>;

/// Simulates the chain with base parameters beta from the reference's first state under the
/// controller: semi-implicit Euler, enough substeps per sample for the stiffest loop (omega h <=
/// 0.05; the motor's lag is updated exactly per substep). Forward dynamics from the base regressor itself
/// (M(q) e_j = Y(q, 0, e_j) phi - Y(q, 0, 0) phi, h = Y(q, qd, 0) phi, phi the standard vector
/// with beta on the base columns), so friction and armature are the model's. Row k: the state at
/// t_k, its acceleration and the motor torque acting then. Not ok (never NaN) when M(q) is not
/// positive definite or a joint strays more than 1 rad from the reference.
ClosedLoopRun simulateChainClosedLoop(const ChainModel& model, const BaseParameters& base, const Eigen::VectorXd& beta,
                                      const ChainController& controller, const ChainReference& reference);

}  // namespace exoid::ident
