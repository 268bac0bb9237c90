#include "exoid/sim/simulate.hpp"

#include "exoid/core/format.hpp"
#include "exoid/sim/four_bar.hpp"
#include "exoid/sim/imu.hpp"
#include "exoid/sim/inverse_dynamics.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace exoid::sim {
namespace {

// Internal record columns (all of them; the table selects).
enum Col : int {
  kT = 0, kQHip, kQKnee, kTauHip, kTauKnee,
  kQHipTrue, kQKneeTrue, kQdHipTrue, kQdKneeTrue, kQddHipTrue, kQddKneeTrue,
  kTauHipTrue, kTauKneeTrue, kTauHipIdeal, kTauKneeIdeal,
  kQHipRef, kQKneeRef, kBaseX, kBaseZ, kBasePitch, kLoopError,
  kTauHipCmd, kTauKneeCmd, kBaseAccX, kBaseAccZ, kBaseGyroY, kNumCols
};
const char* const kColNames[kNumCols] = {
    "t", "q_hip", "q_knee", "tau_hip", "tau_knee",
    "q_hip_true", "q_knee_true", "qd_hip_true", "qd_knee_true", "qdd_hip_true", "qdd_knee_true",
    "tau_hip_true", "tau_knee_true", "tau_hip_ideal", "tau_knee_ideal",
    "q_hip_ref", "q_knee_ref", "base_x", "base_z", "base_pitch", "loop_error",
    "tau_hip_cmd", "tau_knee_cmd", "base_acc_x", "base_acc_z", "base_gyro_y"};
const int kShortCols[] = {kT, kQHip, kQKnee, kTauHip, kTauKnee, kQHipRef, kQKneeRef, kBaseAccX, kBaseAccZ, kBaseGyroY};

template <class T>
[[noreturn]] void badField(const char* field, const T& value, const char* expected) {
  std::ostringstream ss;
  ss.precision(17);
  ss << "'" << field << "' must be " << expected << ", got " << value;
  throw std::invalid_argument(ss.str());
}

Eigen::Index sampleCount(const SimConfig& c) {
  return static_cast<Eigen::Index>(std::llround(c.duration_s / c.dt_s));
}

}  // namespace

void SimConfig::validate() const {
  if (model_path.empty()) badField("model_path", "\"\"", "a path to an MJCF file");
  if (trajectory < 0 || trajectory > 4) badField("trajectory", trajectory, "1..4 (paper Table 1) or 0 (Fourier)");
  if (trajectory == 0) fourier.validate();
  // Bounded like the duration: the ramp is simulated too (1e7 s would be 1e10 steps).
  if (!std::isfinite(ramp_s) || ramp_s < 0 || ramp_s > 600) badField("ramp_s", ramp_s, "in [0, 600] s");
  if (!std::isfinite(dt_s) || dt_s <= 0 || dt_s > 0.01) badField("dt_s", dt_s, "in (0, 0.01] s");
  if (!std::isfinite(duration_s) || duration_s <= 0 || duration_s > 3600) badField("duration_s", duration_s, "in (0, 3600] s");
  if (sampleCount(*this) < 2) badField("duration_s", duration_s, "at least 2 samples (duration >= 2 dt)");
  sensors.validate();
  variant.validate();
  floor.validate();
  if (floor.active() && variant.vibration_level == 0) {
    throw std::invalid_argument("'floor' disturbance needs 'vibration_level' > 0 (a welded pedestal cannot move)");
  }
  gains.validate({"hip", "knee"});
  actuators.validate(dt_s);
  if (sensors.tau_bandwidth_Hz * dt_s >= 0.5) badField("sensors.tau_bandwidth_Hz", sensors.tau_bandwidth_Hz, "below the Nyquist frequency 1 / (2 dt)");
  if (!std::isfinite(max_loop_error_m) || max_loop_error_m <= 0) badField("max_loop_error_m", max_loop_error_m, "> 0");
}

core::FourierSeries SimConfig::trajectorySpec() const { return trajectory == 0 ? fourier : paperTrajectory(trajectory); }

std::vector<std::string> datasetColumns(bool exact_columns) {
  std::vector<std::string> out;
  if (exact_columns) {
    for (int c = 0; c < kNumCols; ++c) out.emplace_back(kColNames[c]);
  } else {
    for (int c : kShortCols) out.emplace_back(kColNames[c]);
  }
  return out;
}

struct Simulator::Impl {
  SimConfig cfg;
  LegModel leg;
  DataPtr data;
  std::optional<FourBar> fb;
  std::optional<IdealInverseDynamics> ideal;
  std::optional<IdealInverseDynamics> controller_model;  // the feedforward's model
  std::optional<Trajectory> traj;
  std::optional<Sensors> sensors;
  std::optional<core::PidController> pid;
  std::optional<Actuators> act;
  std::optional<FloorForce> floor;
  Eigen::MatrixX2d ff_cmd;  // feedforward command per step (pre-roll included), when enabled
  Eigen::Index n = 0;
  // One row per sample, stored row by row: the loop writes one contiguous row per step (the table
  // is column-major; finish() converts once).
  Eigen::Matrix<double, Eigen::Dynamic, kNumCols, Eigen::RowMajor> rec;
  double first_loop_error_m = 0.0;  // after the very first step, pre-roll included
  bool ran = false, finished = false;
  double setup_time_s = 0.0, loop_time_s = 0.0;

  explicit Impl(const SimConfig& c) : cfg(c) {
    const auto t0 = std::chrono::steady_clock::now();
    cfg.validate();
    leg = loadLeg(cfg.model_path, cfg.variant);
    mjModel* m = leg.model.get();
    m->opt.timestep = cfg.dt_s;
    data = makeData(m);
    fb.emplace(m, leg.idx);
    ideal.emplace(loadLeg(cfg.model_path, cfg.variant, /*force_welded=*/true));
    traj.emplace(cfg.trajectorySpec(), cfg.ramp_s);
    sensors.emplace(cfg.sensors, 2, cfg.seed, cfg.dt_s);
    pid.emplace(cfg.gains, cfg.dt_s);
    act.emplace(cfg.actuators, cfg.dt_s);
    floor.emplace(cfg.floor, cfg.seed);
    n = sampleCount(cfg);
    rec.setZero(n, kNumCols);
    if (cfg.feedforward) {
      ModelVariant nominal = cfg.variant;
      if (cfg.feedforward_model == SimConfig::ControllerModel::kRigidLinks) nominal.cylinder_mass_scale = 0.0;
      controller_model.emplace(loadLeg(cfg.model_path, nominal, /*force_welded=*/true));
      planFeedforward();
    }
    initialState();
    setup_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  Eigen::Index preroll() const {
    return cfg.record_after_ramp ? static_cast<Eigen::Index>(std::llround(cfg.ramp_s / cfg.dt_s)) : 0;
  }

  // Model-based feedforward of the planned reference, computed before the run as a rig with a
  // planned trajectory can: the controller model's inverse dynamics at the reference, through the
  // actuators' inverse (derivatives by central differences of the smooth torque plan), so that
  // the joints get the reference torque despite the actuator lag. The hip gets none when locked.
  void planFeedforward() {
    const Eigen::Index steps = preroll() + n;
    Eigen::MatrixX2d tau(steps, 2);
    for (Eigen::Index k = 0; k < steps; ++k) {
      const JointReference r = traj->at(static_cast<double>(k) * cfg.dt_s);
      tau.row(k) = controller_model->torque(r.q, r.qd, r.qdd).transpose();
    }
    if (traj->hipLocked()) tau.col(0).setZero();
    ff_cmd.resize(steps, 2);
    const double dt = cfg.dt_s;
    for (Eigen::Index k = 0; k < steps; ++k) {
      const Eigen::Index a = std::max<Eigen::Index>(k - 1, 0), b = std::min<Eigen::Index>(k + 1, steps - 1);
      const Eigen::Vector2d d1 = (tau.row(b) - tau.row(a)).transpose() / (static_cast<double>(b - a) * dt);
      const Eigen::Vector2d d2 = b - a == 2 ? Eigen::Vector2d((tau.row(b) - 2.0 * tau.row(k) + tau.row(a)).transpose() / (dt * dt))
                                           : Eigen::Vector2d::Zero();
      ff_cmd.row(k) = act->inverse(tau.row(k).transpose(), d1, d2).transpose();
    }
  }

  void initialState() {
    mjModel* m = leg.model.get();
    mjData* d = data.get();
    const LegIndices& x = leg.idx;
    const JointReference r0 = traj->at(0.0);
    mju_zero(d->qpos, m->nq);
    mju_zero(d->qvel, m->nv);
    setLegState(m, d, x, *fb, {r0.q[0], r0.q[1]}, {r0.qd[0], r0.qd[1]});
    const bool locked = traj->hipLocked();
    m->eq_active[x.eq_hip_lock] = locked ? 1 : 0;
    if (locked) {
      // joint equality with joint1 only: q_hip - qpos0 = polycoef[0] (qpos0 = 0).
      m->eq_data[mjNEQDATA * x.eq_hip_lock] = r0.q[0];
      for (int k = 1; k < 5; ++k) m->eq_data[mjNEQDATA * x.eq_hip_lock + k] = 0.0;
    }
    // Pre-load the mount springs so the pedestal starts in static equilibrium under gravity.
    if (!leg.welded) {
      mj_forward(m, d);
      for (int k = 0; k < 3; ++k) {
        const double stiff = m->jnt_stiffness[x.mount_jnt[k]];
        m->qpos_spring[x.mount_qadr[k]] = d->qfrc_bias[x.mount_vadr[k]] / stiff;
      }
    }
    mj_forward(m, d);
    checkStepHealth(m, d, 0.0, "initial state");
    // The rig starts holding the initial pose: the actuators deliver the static holding torque
    // (from the feedforward, else from the PID's preloaded integral) and the torque sensors read it.
    Eigen::Vector2d hold = ideal->torque(r0.q, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero());
    if (locked) hold[0] = 0.0;
    // With feedforward the integral holds what the controller's model misses of the pose.
    const Eigen::Vector2d integral0 = cfg.feedforward ? Eigen::Vector2d(hold - ff_cmd.row(0).transpose()) : hold;
    pid->reset({!locked, true}, integral0);
    act->reset(hold);
    sensors->resetTorqueFilters(hold);
  }

  void run() {
    if (ran) throw std::logic_error("Simulator::run called twice");
    ran = true;
    const auto t0 = std::chrono::steady_clock::now();
    // With record_after_ramp the start ramp runs unrecorded (as a rig is started before its log):
    // rows go to a scratch row until the ramp is over, and the table's t starts at 0 after it.
    const Eigen::Index preroll = this->preroll();
    Eigen::Matrix<double, 1, kNumCols> scratch = Eigen::Matrix<double, 1, kNumCols>::Zero();
    for (Eigen::Index step = 0; step < preroll + n; ++step) {
      const Eigen::Index k = step - preroll;  // record row, negative during the pre-roll
      double* row = k >= 0 ? rec.data() + k * kNumCols : scratch.data();
      row[kT] = static_cast<double>(k) * cfg.dt_s;
      advance(step, row);
    }
    loop_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  // One step at t = step dt (trajectory and disturbance time): the row gets the state, the
  // readings, the command and the forward dynamics at t; then the state is integrated to t + dt.
  void advance(Eigen::Index step, double* row) {
    const mjModel* m = leg.model.get();
    mjData* d = data.get();
    const LegIndices& x = leg.idx;
    const double t = static_cast<double>(step) * cfg.dt_s;
    const JointReference ref = traj->at(t);
    if (leg.kinematic_loop) {
      setLegState(m, d, x, *fb, {d->qpos[x.qadr[0]], d->qpos[x.qadr[1]]}, {d->qvel[x.vadr[0]], d->qvel[x.vadr[1]]});
    }
    const Eigen::Vector2d q(d->qpos[x.qadr[0]], d->qpos[x.qadr[1]]);
    const Eigen::Vector2d qd(d->qvel[x.vadr[0]], d->qvel[x.vadr[1]]);
    recordState(q, qd, ref, row);
    Eigen::Vector2d qm;
    sensors->angles(q, qm);
    row[kQHip] = qm[0];
    row[kQKnee] = qm[1];
    drive(step, t, ref, qm, qd, row);
    // Forward dynamics at the state of time t: qacc and actuator_force of this row. Then the
    // step itself. With RK4 (the model's integrator) mj_RungeKutta reuses this mj_forward as its
    // first stage, exactly as mj_step would; afterwards qacc holds the last stage's value, so
    // it is read here, before integrating.
    mj_forward(m, d);
    checkStepHealth(m, d, t, "mj_forward");
    const Eigen::Vector2d tau(d->actuator_force[x.act[0]], d->actuator_force[x.act[1]]);
    row[kQddHipTrue] = d->qacc[x.vadr[0]];
    row[kQddKneeTrue] = d->qacc[x.vadr[1]];
    const Eigen::Vector3d imu = sensors->imu(pedestalImuTruth(m, d, x));
    row[kBaseAccX] = imu[0];
    row[kBaseAccZ] = imu[1];
    row[kBaseGyroY] = imu[2];
    // Loop error of this row's state (xpos from the mj_forward above).
    const double le = loopError(m, d, x);
    row[kLoopError] = le;
    if (step == 0) first_loop_error_m = le;
    checkLoopClosed(le, t);
    integrateStep(m, d);
    checkStepHealth(m, d, t, "integration");
    row[kTauHipTrue] = tau[0];
    row[kTauKneeTrue] = tau[1];
    Eigen::Vector2d tm;
    sensors->torques(tau, tm);
    row[kTauHip] = tm[0];
    row[kTauKnee] = tm[1];
  }

  // The exact joint state, the reference and the pedestal's pose at t.
  void recordState(const Eigen::Vector2d& q, const Eigen::Vector2d& qd, const JointReference& ref, double* row) const {
    row[kQHipTrue] = q[0];
    row[kQKneeTrue] = q[1];
    row[kQdHipTrue] = qd[0];
    row[kQdKneeTrue] = qd[1];
    row[kQHipRef] = ref.q[0];
    row[kQKneeRef] = ref.q[1];
    if (!leg.welded) {
      const mjData* d = data.get();
      row[kBaseX] = d->qpos[leg.idx.mount_qadr[0]];
      row[kBaseZ] = d->qpos[leg.idx.mount_qadr[1]];
      row[kBasePitch] = d->qpos[leg.idx.mount_qadr[2]];
    }
  }

  // The controller's command on the angle readings qm (PID plus the planned feedforward) through
  // the actuators, the joints' Coulomb friction, and the floor's push on the pedestal.
  void drive(Eigen::Index step, double t, const JointReference& ref, const Eigen::Vector2d& qm, const Eigen::Vector2d& qd, double* row) {
    mjData* d = data.get();
    const LegIndices& x = leg.idx;
    Eigen::Vector2d u = Eigen::Vector2d::Zero();
    pid->update(ref.q, ref.qd, qm, qd, u);
    if (cfg.feedforward) u += ff_cmd.row(step).transpose();
    row[kTauHipCmd] = u[0];
    row[kTauKneeCmd] = u[1];
    const Eigen::Vector2d applied = act->step(u);
    d->ctrl[x.act[0]] = applied[0];
    d->ctrl[x.act[1]] = applied[1];
    d->qfrc_applied[x.vadr[0]] = -leg.coulomb.torque(0, qd[0]);
    d->qfrc_applied[x.vadr[1]] = -leg.coulomb.torque(1, qd[1]);
    if (cfg.floor.active()) {
      double fx, fz;
      floor->at(t, fx, fz);
      d->xfrc_applied[6 * x.body_pedestal + 0] = fx;
      d->xfrc_applied[6 * x.body_pedestal + 2] = fz;
    }
  }

  void checkLoopClosed(double loop_error_m, double t) const {
    if (loop_error_m <= cfg.max_loop_error_m) return;
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "the four-bar loop opened to %.3g m at t = %.6g s (limit max_loop_error_m = %.3g m): "
                  "the simulation is not trustworthy (check gains, timestep, solref)",
                  loop_error_m, t, cfg.max_loop_error_m);
    throw SimulationError(buf);
  }

  // Ideal (vibration-free, rigid-loop) torques at the exact joint states.
  void idealTorques() {
    for (Eigen::Index k = 0; k < n; ++k) {
      auto row = rec.row(k);
      const Eigen::Vector2d tau = ideal->torque({row[kQHipTrue], row[kQKneeTrue]},
                                                {row[kQdHipTrue], row[kQdKneeTrue]},
                                                {row[kQddHipTrue], row[kQddKneeTrue]});
      row[kTauHipIdeal] = tau[0];
      row[kTauKneeIdeal] = tau[1];
    }
  }

  SimStats statistics() const {
    SimStats s;
    const double rad2deg = 180.0 / M_PI;
    auto track = [&](int qcol, int refcol) {
      JointErrorStats e;
      const Eigen::ArrayXd err = (rec.col(qcol) - rec.col(refcol)).array() * rad2deg;
      e.rms_deg = std::sqrt(err.square().mean());
      e.max_deg = err.abs().maxCoeff();
      return e;
    };
    s.tracking_hip = track(kQHipTrue, kQHipRef);
    s.tracking_knee = track(kQKneeTrue, kQKneeRef);
    s.loop_error_max_m = rec.col(kLoopError).maxCoeff();
    s.loop_error_rms_m = std::sqrt(rec.col(kLoopError).array().square().mean());
    s.loop_error_start_m = first_loop_error_m;
    s.base_x_max_abs_m = rec.col(kBaseX).cwiseAbs().maxCoeff();
    s.base_z_max_abs_m = rec.col(kBaseZ).cwiseAbs().maxCoeff();
    s.base_pitch_max_abs_rad = rec.col(kBasePitch).cwiseAbs().maxCoeff();
    s.tau_rms_hip_Nm = std::sqrt(rec.col(kTauHipTrue).array().square().mean());
    s.tau_rms_knee_Nm = std::sqrt(rec.col(kTauKneeTrue).array().square().mean());
    s.loop_time_s = loop_time_s;
    return s;
  }

  // The dataset's columns (all, or the short set a rig logs).
  void fillTable(Table& tb) const {
    tb.names = datasetColumns(cfg.exact_columns);
    if (cfg.exact_columns) {
      tb.values = rec;
    } else {
      tb.values.resize(n, static_cast<Eigen::Index>(std::size(kShortCols)));
      for (std::size_t i = 0; i < std::size(kShortCols); ++i) {
        tb.values.col(static_cast<Eigen::Index>(i)) = rec.col(kShortCols[i]);
      }
    }
  }

  // The dataset's header: the run's settings, and the tracking law, so that methods that simulate
  // the closed loop (IDIM-IV) can rebuild it.
  void addMetadata(const SimResult& r, Table& tb) const {
    auto meta = [&](const std::string& k, const std::string& v) { tb.metadata.emplace_back(k, v); };
    const auto num = [](double v) { return core::formatNumber(v, 17); };
    meta("source", std::string("exoid sim (MuJoCo ") + mj_versionString() + ")");
    meta("model", cfg.model_path);
    meta("model_fnv1a64", r.model_fnv1a64);
    meta("trajectory", cfg.trajectory == 0 ? std::string("fourier") : core::toText(cfg.trajectory));
    meta("hip_locked", traj->hipLocked() ? "true" : "false");
    meta("seed", core::toText(cfg.seed));
    meta("dt_s", num(cfg.dt_s));
    meta("duration_s", num(cfg.duration_s));
    meta("ramp_s", num(cfg.ramp_s));
    meta("record_after_ramp", cfg.record_after_ramp ? "true" : "false");
    meta("thigh_length_m", num(r.truth.thigh_length_m));
    meta("gravity_mps2", num(r.truth.gravity_mps2));
    meta("noise_q_deg", num(cfg.sensors.noise_q_deg));
    meta("quantisation_deg", num(cfg.sensors.quantisation_deg));
    if (cfg.sensors.encoder_backlash_deg > 0) meta("encoder_backlash_deg", num(cfg.sensors.encoder_backlash_deg));
    meta("noise_tau_Nm", num(cfg.sensors.noise_tau_Nm));
    meta("vibration_level", num(cfg.variant.vibration_level));
    meta("cylinder_mass_scale", num(cfg.variant.cylinder_mass_scale));
    meta("feedforward", cfg.feedforward ? "true" : "false");
    const auto pair = [&](const Eigen::Vector2d& v) { return num(v[0]) + "," + num(v[1]); };
    meta("controller_kp_Nm_per_rad", pair(cfg.gains.kp_Nm_per_rad));
    meta("controller_ki_Nm_per_rad_s", pair(cfg.gains.ki_Nm_per_rad_s));
    meta("controller_kd_Nms_per_rad", pair(cfg.gains.kd_Nms_per_rad));
    meta("controller_derivative_cutoff_Hz", num(cfg.gains.derivative_cutoff_Hz));
    meta("controller_integral_limit_Nm", num(cfg.gains.integral_limit_Nm));
    meta("hip_actuator_bandwidth_Hz", num(cfg.actuators.hip_bandwidth_Hz));
    meta("knee_actuator_bandwidth_Hz", num(cfg.actuators.knee_bandwidth_Hz));
    meta("torque_sensor_bandwidth_Hz", num(cfg.sensors.tau_bandwidth_Hz));
    meta("units", "s, rad, rad/s, rad/s^2, N m, m");
  }

  SimResult finish() {
    if (!ran) run();
    if (finished) throw std::logic_error("Simulator::finish called twice");
    finished = true;
    const auto t0 = std::chrono::steady_clock::now();
    SimResult r;
    r.config = cfg;
    idealTorques();
    r.stats = statistics();
    r.truth = rigidTruth(leg);
    r.lumped_band = lumpedBand(leg, rec.col(kQKneeTrue).minCoeff(), rec.col(kQKneeTrue).maxCoeff(), 181);
    r.model_fnv1a64 = toHex(leg.xml_fnv1a64);
    r.model_bytes = leg.xml_bytes;
    r.mujoco_version = mj_versionString();
    fillTable(r.table);
    addMetadata(r, r.table);
    r.stats.wall_time_s = setup_time_s + loop_time_s + std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  }
};

Simulator::Simulator(const SimConfig& config) : impl_(std::make_unique<Impl>(config)) {}
Simulator::~Simulator() = default;
void Simulator::run() { impl_->run(); }
SimResult Simulator::finish() { return impl_->finish(); }

SimResult simulate(const SimConfig& config) {
  Simulator s(config);
  s.run();
  return s.finish();
}

void writeCsv(const SimResult& result, const std::string& path) { writeTableCsv(result.table, path); }

}  // namespace exoid::sim
