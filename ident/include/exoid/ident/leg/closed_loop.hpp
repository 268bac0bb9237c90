#pragma once
// A simulation of the identified rigid model under the rig's tracking controller: what IDIM-IV
// (Janot, Vandanjon, Gautier) needs to build instruments that share the motion but not the
// measurement noise. Pure Eigen: the controller is whatever the user describes, so it serves real
// logs as well as exoid's simulator (whose controller it mirrors: sim/controller.hpp).
#include "exoid/ident/leg/params.hpp"
#include "exoid/ident/leg/regressor.hpp"
#include "exoid/ident/signals/sampled_reference.hpp"

#include <Eigen/Core>

#include <array>
#include <string>

namespace exoid::ident {

/// The tracking law, per joint: u = kp e + ki int(e) + kd de_est, e = q_ref - q, where de_est is
/// the backward difference of e through a first-order low-pass at derivative_cutoff_hz (0 = none),
/// and |ki int(e)| <= integral_limit_Nm. Updated once per sample, held in between.
struct PidLaw {
  Eigen::Vector2d kp_Nm_per_rad{0.0, 0.0};   ///< hip, knee; >= 0
  Eigen::Vector2d ki_Nm_per_rad_s{0.0, 0.0};  ///< >= 0
  Eigen::Vector2d kd_Nms_per_rad{0.0, 0.0};  ///< >= 0
  double derivative_cutoff_hz = 0.0;         ///< >= 0
  double integral_limit_Nm = 1e300;          ///< > 0
};

/// What the controller adds besides feedback.
enum class Feedforward {
  kNone,
  /// The model's own inverse dynamics on the reference, Y(q_ref, qd_ref, qdd_ref) x (computed torque).
  kModel,
};
const char* toString(Feedforward f);  ///< "none", "model"
/// Parses "none" | "model"; throws std::invalid_argument naming the valid values.
Feedforward parseFeedforward(const std::string& name);

struct ControllerModel {
  PidLaw pid;
  Feedforward feedforward = Feedforward::kModel;
  /// A locked joint follows its reference exactly (the rig's fixed hip in the knee-only records).
  std::array<bool, 2> locked{false, false};
  /// Throws std::invalid_argument naming the field (a negative or non-finite gain, no free joint
  /// with a nonzero kp: nothing would hold the motion on the reference).
  void validate() const;
};

/// The reference the controller tracked, sampled like the record (uniform dt).
/// The reference the controller tracked (Reference::fromAngles from recorded reference angles).
using Reference = SampledReference<Eigen::MatrixX2d>;

struct ClosedLoopRun {
  bool ok = false;
  std::string message;  ///< why not ok (e.g. the model's mass matrix is not positive definite)
  JointSignals states;  ///< t, q, qd, qdd of the model; tau = the torque it was driven by
};

/// Simulates the rigid model x from the reference's first state (tracking error 0; without
/// feedforward, an integral term preloaded with the gravity torque there) under the controller, semi-implicit Euler with
/// enough substeps per sample for the stiffest loop (omega dt <= 0.05). Forward dynamics from the
/// regressor itself: M(q) e_j = Y(q, 0, e_j) x - Y(q, 0, 0) x, h = Y(q, qd, 0) x. Not ok (never
/// NaN) when M(q) is not positive definite or the tracking error exceeds 1 rad.
/// knee_armature_kgm2: the optional 11th parameter Ia2 (adds Ia2 qdd2 to the knee torque).
ClosedLoopRun simulateClosedLoop(const ParamVector& x, const LegConstants& c, const ControllerModel& ctl,
                                 const Reference& ref, double knee_armature_kgm2 = 0.0);

}  // namespace exoid::ident
