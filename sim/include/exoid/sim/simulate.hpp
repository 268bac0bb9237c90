#pragma once
// The top-level simulation API: one configuration in, a recorded dataset, truths and
// statistics out.
//
// Per sample k (t = k dt, controller and sensors at 1/dt):
//   1. read the exact state (q, qd) and the pedestal state; the encoder reads q;
//   2. the PID plus the planned feedforward computes the torque commands from the readings, and
//      the actuators (finite bandwidth) turn them into the torques the joints get;
//   3. Coulomb friction -fc tanh(qd/v0) goes into qfrc_applied, the floor force into
//      xfrc_applied of the pedestal;
//   4. mj_forward: qacc (acceleration of the state of step 1 under these torques), actuator_force
//      (the joint torque) and the pedestal IMU complete row k; the torque sensor (anti-aliasing
//      filter, noise) reads the joint torque; then the integrator advances the state;
//   5. warnings, finite state and the loop error are checked: any failure throws.
// Row k therefore satisfies the continuous-time dynamics exactly: tau_true(k) is the torque
// that produced qdd_true(k) at (q_true(k), qd_true(k)).
#include "exoid/sim/actuators.hpp"
#include "exoid/core/pid.hpp"
#include "exoid/sim/model.hpp"
#include "exoid/sim/sensors.hpp"
#include "exoid/sim/table.hpp"
#include "exoid/sim/trajectory.hpp"
#include "exoid/sim/truth.hpp"
#include "exoid/sim/vibration.hpp"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace exoid::sim {

/// The APAL rig's feedback (hip, knee), that of a rig with model-based feedforward: a critically
/// damped position loop at wn = 2 pi 4 Hz on the joint inertias (hip J ~ 3.5 kg m^2, knee ~ 0.6
/// kg m^2 with the cylinder): kp = J wn^2, kd = 2 J wn, well below the knee's 20 Hz force loop; a
/// slow integral (wi = 2 pi 0.5 Hz) for what the model misses; the error difference through a
/// 100 Hz low-pass (>10x the position loop: the usual compromise between lag and encoder noise).
inline core::PidGains apalLegGains() {
  core::PidGains g;
  g.kp_Nm_per_rad = Eigen::Vector2d(2200.0, 380.0);
  g.ki_Nm_per_rad_s = Eigen::Vector2d(6900.0, 1200.0);
  g.kd_Nms_per_rad = Eigen::Vector2d(176.0, 30.0);
  return g;
}

struct SimConfig {
  std::string model_path = defaultModelPath();  ///< MJCF file
  /// Paper Table 1 trajectory 1..4, or 0 to use `fourier`.
  int trajectory = 3;
  /// Used when trajectory == 0: hip and knee (the hip locked when locked_joints is 1).
  core::FourierSeries fourier = core::FourierSeries::still(2, 0, 1.0);
  double ramp_s = 1.0;          ///< smooth start (Trajectory), >= 0
  double duration_s = 10.0;     ///< recorded time, > 0 (samples = round(duration / dt))
  /// Run the start ramp before recording: the log starts (t = 0) ramp_s after the motion
  /// started, in periodic motion (a rig's log, too, starts after the robot is under way).
  /// With false the ramp is recorded from t = 0.
  bool record_after_ramp = true;
  double dt_s = 1e-3;           ///< sample, control and integration step, in (0, 0.01]
  SensorOptions sensors;
  ModelVariant variant;         ///< cylinder mass scale, vibration level, friction overrides
  FloorDisturbance floor;       ///< needs variant.vibration_level > 0 when active
  core::PidGains gains = apalLegGains();
  ActuatorOptions actuators;    ///< command -> joint torque bandwidth of the hip motor and knee hydraulics
  /// Model-based feedforward: the ideal rig's inverse dynamics (IdealInverseDynamics) at the
  /// reference, passed through the actuators' inverse, planned before the run; the PID only
  /// corrects. false = PID alone (then the default gains track poorly: they assume feedforward).
  bool feedforward = true;
  /// The controller's model for the feedforward. Default kRigidLinks: the CAD model of the rigid
  /// links, without the hydraulic cylinder's and rod's moving mass (a nominal model, as a rig
  /// has; the feedback absorbs the difference). kRig: the rig exactly as simulated.
  enum class ControllerModel { kRigidLinks, kRig };
  ControllerModel feedforward_model = ControllerModel::kRigidLinks;
  std::uint64_t seed = 1;       ///< all randomness (sensors, floor) derives from it
  /// Write the exact/ground-truth columns (see simulate()); false = t, q, tau, q_ref only.
  bool exact_columns = true;
  /// The run stops with SimulationError when the loop opens more than this (m), > 0.
  double max_loop_error_m = 1e-3;
  /// Throws std::invalid_argument naming the field and the value.
  void validate() const;
  /// The trajectory spec this configuration runs.
  core::FourierSeries trajectorySpec() const;
};

struct JointErrorStats {
  double rms_deg = 0.0, max_deg = 0.0;  ///< of q_true - q_ref over the record
};

struct SimStats {
  JointErrorStats tracking_hip, tracking_knee;
  double loop_error_max_m = 0.0, loop_error_rms_m = 0.0, loop_error_start_m = 0.0;
  double base_x_max_abs_m = 0.0, base_z_max_abs_m = 0.0, base_pitch_max_abs_rad = 0.0;
  double tau_rms_hip_Nm = 0.0, tau_rms_knee_Nm = 0.0;   ///< of the exact motor torques
  double wall_time_s = 0.0;     ///< simulate() total (not deterministic; sidecar only)
  double loop_time_s = 0.0;     ///< stepping loop only
};

struct SimResult {
  SimConfig config;
  Table table;                  ///< the dataset (columns below)
  Truth truth;                  ///< rigid-link X of the model as run (friction overrides included)
  ParamBand lumped_band;        ///< X(q2) band over the record's knee range (cylinder scale as run)
  SimStats stats;
  std::string model_fnv1a64;    ///< hex hash of the MJCF bytes
  std::size_t model_bytes = 0;
  std::string mujoco_version;   ///< mj_versionString()
};

/// Column names. Required: t,q_hip,q_knee,tau_hip,tau_knee (measured); the pedestal IMU
/// base_acc_x, base_acc_z (m/s^2, accelerometer specific force in the trunk frame: +9.81 on z at
/// rest) and base_gyro_y (rad/s, pitch rate), noisy like the sensor. Exact columns:
/// q_*_true, qd_*_true, qdd_*_true, tau_*_true (noise-free motor torques), tau_*_ideal
/// (IdealInverseDynamics at the exact joint states: the torques of a vibration-free rig; in
/// trajectories 1-2 tau_hip_ideal is what the hip lock carries), q_*_ref, base_x, base_z,
/// base_pitch (pedestal mount coordinates, 0 when welded), loop_error (m), tau_*_cmd (the
/// controller's command before the actuators).
std::vector<std::string> datasetColumns(bool exact_columns);

/// Stepping state, exposed for benchmarks: construct (loads models, allocates the table), run()
/// (the per-sample loop, allocation-free), finish() (ideal torques, truths, stats).
class Simulator {
 public:
  explicit Simulator(const SimConfig& config);
  ~Simulator();
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;
  void run();
  SimResult finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Validates, simulates, records. Throws std::invalid_argument (bad config), MujocoError (model)
/// or SimulationError (divergence, open loop).
SimResult simulate(const SimConfig& config);

/// Writes result.table as the dataset CSV (atomic).
void writeCsv(const SimResult& result, const std::string& path);

}  // namespace exoid::sim
