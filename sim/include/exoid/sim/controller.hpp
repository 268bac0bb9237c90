#pragma once
// Joint tracking feedback at the sample rate, for every rig: PID on the encoder readings. The
// error e = q_ref - q_meas; its derivative either a first-order low-pass filtered backward
// difference of e itself (the APAL rig: the reference and the measurement see the same filter
// lag, so the D term does not fight the feedforward) or qd_ref - qd_meas from a tachometer (the
// motor rig; unfiltered, as ident's closed-loop model has it): u = kp e + ki int(e) + kd de_est.
#include <Eigen/Core>

#include <string>
#include <vector>

namespace exoid::sim {

enum class DerivativeSource { kErrorDifference, kMeasuredVelocity };

/// One entry per joint. Defaults: the APAL leg's (hip, knee), the feedback of a rig with
/// model-based feedforward, a critically damped position loop at wn = 2 pi 4 Hz on the joint
/// inertias (hip J ~ 3.5 kg m^2, knee ~ 0.6 kg m^2 with the cylinder): kp = J wn^2, kd = 2 J wn,
/// well below the knee's 20 Hz force loop; a slow integral (wi = 2 pi 0.5 Hz) for what the model
/// misses.
struct PidGains {
  Eigen::VectorXd kp_Nm_per_rad = Eigen::Vector2d(2200.0, 380.0);   ///< >= 0
  Eigen::VectorXd ki_Nm_per_rad_s = Eigen::Vector2d(6900.0, 1200.0);  ///< >= 0
  Eigen::VectorXd kd_Nms_per_rad = Eigen::Vector2d(176.0, 30.0);    ///< >= 0
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

}  // namespace exoid::sim
