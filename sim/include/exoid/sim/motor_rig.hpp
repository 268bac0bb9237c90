#pragma once
// Any serial chain's rig: an MJCF whose motors drive hinge joints (models/leg3.xml, or a user's
// model), run along a Fourier reference per joint, on a rigid stand or on a compliant mount (the
// MJCF's joints of class "mount" between the world and the chain, as the APAL leg's pedestal;
// vibration_level scales them). Per sample k (t = k dt):
//   1. the sensors read the exact state: angles through play, white noise and quantisation
//      (sensors.hpp, the APAL rig's); velocities exact (a tachometer: the controller's, not the
//      log's); on a mount, the base IMU (specific force x, z and pitch rate of the frame the chain
//      is mounted in);
//   2. the controller: MuJoCo's own inverse dynamics at the reference (mj_inverse) plus the
//      model's Coulomb term, and PD feedback on the readings, tuned per joint to bandwidth_hz
//      from the joint-space inertia at the start; the motor follows the command through a
//      first-order lag (actuator_bandwidth_hz);
//   3. Coulomb friction -fc tanh(qd / v0) (or -fc sgn(qd) with v0 = 0) into qfrc_applied;
//   4. mj_forward: qacc and the joint torque (qfrc_actuator) complete row k, the torque sensor adds
//      its noise; the model's integrator advances the state, in substeps where the smoothed
//      Coulomb term is stiff (ChainSimResult::substeps), the friction following the velocity.
// Row k satisfies the dynamics exactly: tau_true(k) produced qdd_true(k) at (q_true(k), qd_true(k)).
#include "exoid/core/fourier_series.hpp"
#include "exoid/sim/sensors.hpp"
#include "exoid/sim/serial_chain.hpp"
#include "exoid/sim/table.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace exoid::sim {

/// A default excitation for a chain: 5 harmonics of 0.1 Hz per joint, coefficients drawn from
/// `seed`; each joint about the middle of its range, within 35 % of the range's width of it (at
/// most 0.6 rad), or about 0 within 0.6 rad when the joint has no range. (`exoid excite --model`
/// designs better ones.)
core::FourierSeries defaultChainTrajectory(const SerialChain& chain, std::uint64_t seed = 1);

/// SensorOptions with an ideal torque sensor (no anti-aliasing filter): the chain rig's default.
SensorOptions idealTorqueSensing();

/// True when the model at `model_path` stands on a compliant mount (joints between the world and
/// the chain: what vibration_level > 0 needs); a URDF's chain always does (urdf_rig.hpp).
/// Throws std::invalid_argument as simulateChain does.
bool hasCompliantMount(const std::string& model_path);

/// A locked joint's added rotor inertia: 1e9 kg m^2 against a leg's ~1 kg m^2, so the reaction of
/// the links below accelerates it by ~1e-9 of their own and the coupling it feeds back is ~1e-9 N m.
inline constexpr double kLockInertia_kgm2 = 1e9;

struct ChainSimConfig {
  std::string model_path;        ///< MJCF (motors on hinge joints) or URDF (urdf_rig.hpp)
  /// A URDF tree's chain (base, tip, held joints), as identify reads it; empty: the file whole.
  ChainSelection selection;
  core::FourierSeries trajectory;  ///< empty (no joints) = defaultChainTrajectory(dof, seed)
  double duration_s = 30.0;      ///< > 0
  double dt_s = 1e-3;            ///< (0, 0.01]; the model's timestep is set to it
  /// Encoders (noise, quantisation, play), torque sensors (noise, bias, bandwidth) and the base
  /// IMU, as the APAL rig's; the chain rig's torque sensor is ideal (tau_bandwidth_Hz 0) unless set.
  SensorOptions sensors = idealTorqueSensing();
  /// The mount's compliance: 0 = a rigid stand (the MJCF's "mount" joints removed, the base exactly
  /// still); L > 0 scales the MJCF's mount stiffness by 1/L^2 and damping by 1/L (natural
  /// frequencies / L), as the APAL leg's vibration_level. Needs mount joints when > 0. [0, 20].
  double vibration_level = 0.0;
  /// Coulomb smoothing: < 0 = the model's exoid_coulomb_v0 (2 mrad/s if absent), 0 = sgn(qd)
  /// exactly (the regressor's own shape: exact data are then exact).
  double coulomb_v0_radps = -1.0;
  double bandwidth_hz = 4.0;     ///< PD closed-loop natural frequency, > 0
  /// The feedback's integral (the APAL rig's PID, core/pid.hpp): ki = kp 2 pi integral_hz
  /// per joint, 0 = PD; |integral term| <= integral_limit_Nm.
  double integral_hz = 0.0;
  double integral_limit_Nm = 500.0;
  /// The motor torque follows the command through a first-order lag of this bandwidth (Hz), so it
  /// is continuous in time as a real drive's; 0 = the command at once, a staircase held over each
  /// sample (then angle-differentiated accelerations lag the recorded torque by about half a
  /// sample: measured, -12 % on leg3's hip.fv). >= 0. Default 100.
  double actuator_bandwidth_hz = 100.0;
  /// The model's inverse dynamics and Coulomb friction at the reference as the command's
  /// feedforward (a rig's computed torque); false = the feedback alone, as the APAL rig's
  /// --no-feedforward (its gains assume the feedforward: tracking is then poorer).
  bool feedforward = true;
  /// Also write qd_<joint>, qdd_<joint>: the exact derivatives, as a rig that logs them.
  bool record_derivatives = false;
  /// Joints locked at the trajectory's offset (the segmental strategy's proximal joints, as the
  /// APAL rig's hip lock): their excitation is removed and their rotor inertia raised by
  /// kLockInertia_kgm2, so the lock, not the motor, carries their load; they move < 1e-5 rad. Their
  /// recorded torque is the motor's command (the feedforward's holding torque, about 0 without
  /// the feedforward), which no identification should use.
  std::vector<std::string> locked;
  std::uint64_t seed = 1;        ///< the sensors' noise (and the default trajectory)
  void validate() const;         ///< throws std::invalid_argument naming the field
};

struct ChainSimResult {
  ChainSimConfig config;         ///< as run (trajectory filled in)
  SerialChain chain;             ///< the model's chain and true bodies (Coulomb as run)
  /// t, q_<j>, tau_<j> (measured) [, qd_<j>, qdd_<j>], q_<j>_true, qd_<j>_true, qdd_<j>_true,
  /// tau_<j>_true, q_<j>_ref, per joint in the chain's order; on a mount, the base IMU's
  /// base_acc_x, base_acc_z, base_gyro_y (as measured; with record_derivatives also the exact pitch
  /// acceleration base_alpha_y) and the base frame's exact displacement base_x, base_z (m) and
  /// pitch base_pitch (rad) from rest.
  Table table;
  double tracking_rms_rad = 0.0;  ///< of q_true - q_ref, all joints
  int substeps = 1;  ///< integration substeps per sample (stiff smoothed Coulomb terms need them)
  /// The controller's PD gains per joint (from the joint-space inertia at the start), also in the
  /// table's metadata (controller_kp_Nm_per_rad, ...) for IDIM-IV.
  Eigen::VectorXd kp_Nm_per_rad, ki_Nm_per_rad_s, kd_Nms_per_rad;
  std::string mujoco_version;
};

/// Throws std::invalid_argument (bad config or model), MujocoError, SimulationError (divergence).
ChainSimResult simulateChain(const ChainSimConfig& config);

}  // namespace exoid::sim
