#pragma once
// A robot's identified model simulated under its rig's tracking controller: what IDIM-IV (Janot,
// Vandanjon, Gautier) needs to build instruments that share the motion of a record but not its
// measurement noise. Pure Eigen: the controller is whatever the user describes, so it serves real
// logs as well as exoid's simulators, whose feedback law it runs (core/pid.hpp, both rigs').
#include "exoid/core/pid.hpp"
#include "exoid/ident/model/robot.hpp"
#include "exoid/ident/signals/sampled_reference.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace exoid::ident {

/// What the controller adds besides feedback.
enum class Feedforward {
  kNone,
  /// The model's own inverse dynamics on the reference, Y(q_ref, qd_ref, qdd_ref) theta (computed torque).
  kModel,
};
/// Parses "none" | "model"; throws std::invalid_argument naming the valid values.
Feedforward parseFeedforward(const std::string& name);

/// Where the feedback's derivative term comes from: the error's filtered difference (the APAL
/// rig's PID) or the measured velocity (a chain rig's tachometer).
using DerivativeSource = core::DerivativeSource;

/// The tracking law, per joint j: u_j = ff_j + kp_j e_j + ki_j int(e_j) + kd_j de_j, updated once
/// per sample and held; |ki int(e)| <= integral_limit_Nm. The motor torque follows u through a
/// first-order lag of actuator_bandwidth_hz (0 = at once). A locked joint follows its reference
/// exactly (a rig's lock: the APAL leg's fixed hip, a segmental stage's proximal joints).
struct Controller {
  Eigen::VectorXd kp_Nm_per_rad;    ///< one per joint, >= 0 (> 0 on some free joint)
  Eigen::VectorXd ki_Nm_per_rad_s;  ///< one per joint, >= 0; empty = none
  Eigen::VectorXd kd_Nms_per_rad;   ///< one per joint, >= 0
  DerivativeSource derivative = DerivativeSource::kErrorDifference;
  double derivative_cutoff_hz = 0.0;   ///< kErrorDifference's low-pass, >= 0 (0 = unfiltered)
  double integral_limit_Nm = 1e300;    ///< > 0
  Feedforward feedforward = Feedforward::kModel;
  double actuator_bandwidth_hz = 0.0;  ///< >= 0
  std::vector<bool> locked;            ///< one per joint; empty = none locked
  bool isLocked(int j) const { return !locked.empty() && locked[static_cast<std::size_t>(j)]; }
  /// Throws std::invalid_argument naming the field and joint: sizes other than the joints', a
  /// negative or non-finite gain, a free joint without kp > 0 (nothing would hold it on the
  /// reference), every joint locked.
  void validate(const std::vector<std::string>& joints) const;
};

/// The reference the controller tracked, sampled like the record (uniform dt): samples x joints.
using Reference = SampledReference;

struct ClosedLoopRun {
  bool ok = false;
  std::string message;  ///< why not ok (e.g. the model's mass matrix is not positive definite)
  JointSignals states;  ///< t, q, qd, qdd of the model; tau = the motor torque acting then
};

/// Simulates the robot with parameters theta from the reference's first state under the
/// controller (without feedforward, an integral term preloaded with the gravity torque there):
/// semi-implicit Euler with enough substeps per sample for the stiffest loop at the start (omega
/// h <= 0.05, omega = max(sqrt(kp / Mjj), kd / Mjj)); the motor's lag is updated exactly for the
/// held command. Forward dynamics from the robot's own rows (robotTorque): M(q) e_j = Y(q, 0, e_j)
/// theta - Y(q, 0, 0) theta, h = Y(q, qd, 0) theta, so friction and armature are the model's. Row
/// k: the state at t_k, its acceleration and the motor torque. Not ok (never NaN) when M(q) is not
/// positive definite on the free joints, a joint strays more than 1 rad from the reference, or the
/// loop is stiffer than 1000 substeps a sample (the gains of a locked joint?). Throws
/// std::invalid_argument for sizes or a controller that do not fit the robot.
ClosedLoopRun simulateClosedLoop(const Robot& robot, const Eigen::VectorXd& theta, const Controller& controller,
                                 const Reference& reference);

}  // namespace exoid::ident
