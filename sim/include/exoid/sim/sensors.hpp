#pragma once
// Sensors at the control rate, for any number of joints: joint encoders (play, noise,
// quantisation), joint torque sensors (anti-aliasing low-pass, then bias and white noise) and a
// base IMU (accelerometer x, z and pitch gyro), every rig's.
#include "exoid/sim/lowpass.hpp"
#include "exoid/sim/random.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace exoid::sim {

struct SensorOptions {
  /// Encoder white noise, standard deviation (deg), >= 0. Added before quantisation.
  double noise_q_deg = 0.0;
  /// Encoder resolution (deg per count), >= 0; 0 = no quantisation. Reading = round(x/r) r.
  double quantisation_deg = 0.0;
  /// Play between each joint and its encoder (deg, in [0, 90)), e.g. a motor-side encoder reading
  /// the joint through a gear's backlash: the reading follows the joint only once the joint has
  /// taken up the play (a play operator: r = clamp(r, q - b/2, q + b/2)), so at every reversal it
  /// stands still while the joint moves b. The angles then carry motion the joint torque does not
  /// drive (errors-in-variables in the regressor columns, as on the DFKI double pendulum's logs),
  /// and the controller, which reads the same encoder, reacts to it. Applied before noise and
  /// quantisation. 0 = none (default).
  double encoder_backlash_deg = 0.0;
  /// Torque sensor white noise, standard deviation (N m), >= 0.
  double noise_tau_Nm = 0.0;
  /// Constant torque sensor bias (N m) per joint, base to tip (the APAL leg: hip, knee); finite,
  /// within 1 kN m. Empty = none; else one per joint.
  std::vector<double> tau_bias_Nm;
  /// Torque sensor bandwidth (Hz): a 2nd-order Butterworth anti-aliasing low-pass ahead of the
  /// 1 kHz sampling (strain-gauge amplifier + filter; an engineering choice of fs / 5, see
  /// models/README.md). 0 = ideal sensor. Must be below Nyquist. Its delay, sqrt(2) / (2 pi fc) =
  /// 1.1 ms at 200 Hz, is part of a real rig's torque record.
  double tau_bandwidth_Hz = 200.0;
  /// Base (pedestal) IMU white noise per sample (datasheet noise density times sqrt(fs / 2), TDK
  /// ICM-42688-P: 70 ug/sqrt(Hz) -> 0.0154 m/s^2, 0.0028 deg/s/sqrt(Hz) -> 1.09e-3 rad/s at 1 kHz).
  double imu_acc_noise_mps2 = 0.0154;
  double imu_gyro_noise_radps = 1.09e-3;
  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

class Sensors {
 public:
  /// joints: how many; dt_s: the sample interval (the torque filters are discretised for it).
  /// Throws std::invalid_argument for options that do not fit (a bias per joint, when given).
  Sensors(const SensorOptions& o, int joints, std::uint64_t seed, double dt_s);
  /// Encoder readings (rad) of the true angles (rad), joint by joint (allocation-free).
  void angles(const Eigen::Ref<const Eigen::VectorXd>& q_true_rad, Eigen::Ref<Eigen::VectorXd> reading);
  /// Torque readings (N m) of the torques the joints get this sample (anti-aliasing filter,
  /// then bias and noise).
  void torques(const Eigen::Ref<const Eigen::VectorXd>& tau_true_Nm, Eigen::Ref<Eigen::VectorXd> reading);
  /// The same, allocated.
  Eigen::VectorXd angles(const Eigen::Ref<const Eigen::VectorXd>& q_true_rad);
  Eigen::VectorXd torques(const Eigen::Ref<const Eigen::VectorXd>& tau_true_Nm);
  /// Starts the torque sensors' filters in steady state at these torques.
  void resetTorqueFilters(const Eigen::Ref<const Eigen::VectorXd>& tau_Nm);
  /// IMU readings [acc_x, acc_z, gyro_y] of the true values (noise added).
  Eigen::Vector3d imu(const Eigen::Vector3d& truth);

 private:
  SensorOptions o_;
  double noise_q_rad_, quant_rad_, backlash_rad_;
  std::vector<double> play_;  ///< the play operator's state (the encoder side), per joint
  bool play_started_ = false;
  Rng enc_, tau_, imu_;
  std::vector<SecondOrderLowpass> tau_filter_;
};

}  // namespace exoid::sim
