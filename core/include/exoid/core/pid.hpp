#pragma once
// Joint tracking feedback at the sample rate: PID on the encoder readings, the one law of every
// simulated rig (sim) and of ident's model of a rig's controller (ident/model/closed_loop.hpp), so
// the model runs the rig's arithmetic. The error e = q_ref - q_meas; its derivative either a
// first-order low-pass filtered backward difference of e itself (the APAL rig: the reference and
// the measurement see the same filter lag, so the D term does not fight the feedforward) or
// qd_ref - qd_meas from a tachometer (the motor rig; unfiltered): u = kp e + ki int(e) + kd de_est.
#include <Eigen/Core>

#include <string>
#include <vector>

namespace exoid::core {

/// Where the feedback's derivative term comes from.
enum class DerivativeSource {
  /// The backward difference of e through a first-order low-pass at derivative_cutoff_Hz (0 = none).
  kErrorDifference,
  /// qd_ref - qd with the measured velocity (a tachometer).
  kMeasuredVelocity,
};

/// One entry per joint (sim::apalLegGains() are the APAL rig's).
struct PidGains {
  Eigen::VectorXd kp_Nm_per_rad;    ///< >= 0
  Eigen::VectorXd ki_Nm_per_rad_s;  ///< >= 0
  Eigen::VectorXd kd_Nms_per_rad;   ///< >= 0
  DerivativeSource derivative = DerivativeSource::kErrorDifference;
  /// Cutoff of the error difference's low-pass (Hz); 0 = unfiltered. 100 Hz: >10x the position loop,
  /// the usual compromise between lag and encoder noise.
  double derivative_cutoff_Hz = 100.0;
  /// Anti-windup: |integral term| <= this (N m), > 0.
  double integral_limit_Nm = 500.0;
  int dof() const { return static_cast<int>(kp_Nm_per_rad.size()); }
  /// Throws std::invalid_argument naming the field and the joint (`joints`: one name per gain;
  /// empty: the joints by number, as many as kp has).
  void validate(const std::vector<std::string>& joints = {}) const;
};

class PidController {
 public:
  PidController(const PidGains& g, double dt_s);
  /// Starts from rest (the first sample's error difference is taken as 0); `enabled[j] = false`
  /// makes joint j's feedback 0 (a locked hip). `integral0_Nm` (empty = 0) preloads the integral
  /// term (e.g. the static holding torque of the initial pose, as if the controller had been
  /// holding the leg before the record).
  void reset(const std::vector<bool>& enabled, const Eigen::VectorXd& integral0_Nm = {});
  /// Adds the feedback to `command` (the feedforward so far, or zeros), term by term (kp e, the
  /// integral, kd de_est). qd_meas is read only for kMeasuredVelocity. Allocation-free.
  void update(const Eigen::Ref<const Eigen::VectorXd>& q_ref, const Eigen::Ref<const Eigen::VectorXd>& qd_ref,
              const Eigen::Ref<const Eigen::VectorXd>& q_meas, const Eigen::Ref<const Eigen::VectorXd>& qd_meas,
              Eigen::Ref<Eigen::VectorXd> command);

 private:
  PidGains g_;
  double dt_, alpha_;
  Eigen::VectorXd e_prev_, e_dot_est_, integral_;
  bool first_ = true;
  std::vector<bool> enabled_;
};

}  // namespace exoid::core
