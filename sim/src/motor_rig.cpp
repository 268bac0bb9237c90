#include "exoid/sim/motor_rig.hpp"

#include "exoid/core/format.hpp"
#include "exoid/core/pid.hpp"
#include "exoid/sim/urdf_rig.hpp"
#include "exoid/sim/model.hpp"
#include "exoid/sim/mujoco_hooks.hpp"
#include "exoid/sim/random.hpp"
#include "exoid/sim/serial_chain.hpp"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>

namespace exoid::sim {

namespace {

constexpr double kTwoPi = 6.283185307179586;

std::string jointName(const mjModel* m, int j) {
  const char* n = mj_id2name(m, mjOBJ_JOINT, j);
  return n ? n : "joint" + std::to_string(j);
}


}  // namespace

core::FourierSeries defaultChainTrajectory(const SerialChain& chain, std::uint64_t seed) {
  const int dof = static_cast<int>(chain.links.size());
  if (dof < 1) throw std::invalid_argument("default trajectory: the chain has no joints");
  constexpr int kHarmonics = 5;
  Rng rng(core::deriveSeed(seed, 101));
  core::FourierSeries f = core::FourierSeries::still(dof, kHarmonics, 0.1);
  for (int j = 0; j < dof; ++j) {
    const ChainLinkBody& l = chain.links[static_cast<std::size_t>(j)];
    double amplitude = 0.6;
    if (std::isfinite(l.q_min_rad) && std::isfinite(l.q_max_rad)) {
      f.offset_rad[j] = 0.5 * (l.q_min_rad + l.q_max_rad);
      amplitude = std::min(amplitude, 0.35 * (l.q_max_rad - l.q_min_rad));
    }
    for (int k = 0; k < kHarmonics; ++k) {
      f.b_rad(k, j) = rng.uniform(-1.0, 1.0);
      f.a_rad(k, j) = rng.uniform(-1.0, 1.0);
    }
    // |q - offset| <= the sum of |coefficients| = amplitude.
    double sum_b = 0.0, sum_a = 0.0;
    for (int k = 0; k < kHarmonics; ++k) sum_b += std::abs(f.b_rad(k, j));
    for (int k = 0; k < kHarmonics; ++k) sum_a += std::abs(f.a_rad(k, j));
    f.b_rad.col(j) *= amplitude / (sum_b + sum_a);
    f.a_rad.col(j) *= amplitude / (sum_b + sum_a);
  }
  return f;
}

SensorOptions idealTorqueSensing() {
  SensorOptions o;
  o.tau_bandwidth_Hz = 0.0;
  return o;
}

void ChainSimConfig::validate() const {
  auto need = [](bool ok, const char* field, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("chain simulation: '") + field + "' must be " + what);
  };
  need(!model_path.empty(), "model_path", "a model file");
  need(selection.empty() || isUrdfFile(model_path), "selection", "empty for an MJCF (simulated as it is; a chain is chosen out of a URDF's tree)");
  need(duration_s > 0.0 && std::isfinite(duration_s), "duration_s", "> 0");
  need(dt_s > 0.0 && dt_s <= 0.01, "dt_s", "in (0, 0.01]");
  sensors.validate();
  need(sensors.tau_bandwidth_Hz * dt_s < 0.5, "sensors.tau_bandwidth_Hz", "below the Nyquist frequency 1 / (2 dt)");
  need(vibration_level >= 0.0 && vibration_level <= 20.0, "vibration_level", "in [0, 20] (0 = a rigid stand)");
  need(std::isfinite(coulomb_v0_radps), "coulomb_v0_radps", "a number (< 0: the model's, 0: sgn)");
  need(bandwidth_hz > 0.0 && bandwidth_hz < 0.1 / dt_s, "bandwidth_hz", "in (0, 0.1 / dt_s)");
  need(integral_hz >= 0.0 && integral_hz < bandwidth_hz, "integral_hz", "in [0, bandwidth_hz) (0 = PD)");
  need(integral_limit_Nm > 0.0 && std::isfinite(integral_limit_Nm), "integral_limit_Nm", "> 0");
  need(actuator_bandwidth_hz >= 0.0 && std::isfinite(actuator_bandwidth_hz), "actuator_bandwidth_hz", ">= 0");
  if (trajectory.dof() > 0) trajectory.validate();
}

namespace {

// The rig's model: on a rigid stand (the file's mount joints removed from its text, so the base is
// exactly still) at vibration level 0, else the file as it is.
ModelPtr loadChainRig(const ChainSimConfig& config) {
  if (isUrdfFile(config.model_path)) {
    // A URDF has no motors and no stand: its chain (out of a tree by the selection) as an MJCF with both (urdf_rig.hpp).
    return compileUrdfRig(config.model_path, config.selection, config.vibration_level > 0.0);
  }
  if (config.vibration_level == 0.0) {
    const std::string xml = readFileBytes(config.model_path);
    if (xml.find("class=\"mount\"") != std::string::npos) {
      return compileMjcf(stripMountJoints(xml, config.model_path), "'" + config.model_path + "' (mount removed)");
    }
  }
  return loadMjcfFile(config.model_path);
}

// The chain's driven joints in the model: names, Coulomb friction, addresses and motors.
struct DrivenJoints {
  std::vector<int> ids;
  std::vector<int> mount;  ///< the mount's joints (every other joint: between the world and the chain)
  std::vector<std::string> names;
  std::vector<double> coulomb;
  std::vector<int> dofadr, qposadr, actuator;
  int dof() const { return static_cast<int>(ids.size()); }
  int dofAdr(int i) const { return dofadr[static_cast<std::size_t>(i)]; }
  int qposAdr(int i) const { return qposadr[static_cast<std::size_t>(i)]; }
};

DrivenJoints drivenJoints(const mjModel* m, const std::string& path) {
  DrivenJoints j;
  j.ids = drivenHinges(m, path);
  const int dof = j.dof();
  // Every other joint must be the mount's: a slide or hinge above the chain's first link.
  const int first_body = m->jnt_bodyid[j.ids.front()];
  for (int k = 0; k < m->njnt; ++k) {
    if (std::find(j.ids.begin(), j.ids.end(), k) != j.ids.end()) continue;
    bool above = false;
    for (int b = m->body_parentid[first_body]; b > 0 && !above; b = m->body_parentid[b]) above = m->jnt_bodyid[k] == b;
    if (!above || (m->jnt_type[k] != mjJNT_SLIDE && m->jnt_type[k] != mjJNT_HINGE)) {
      throw std::invalid_argument("chain simulation: '" + path + "' has joint '" + jointName(m, k) + "' that no motor drives and that is not " +
                                  "a mount's (a slide or hinge between the world and the chain): a passive joint or a free base is not a " +
                                  "serial chain exoid simulates");
    }
    j.mount.push_back(k);
  }
  const auto n = static_cast<std::size_t>(dof);
  j.coulomb.resize(n);
  j.names.resize(n);
  j.dofadr.resize(n);
  j.qposadr.resize(n);
  j.actuator.assign(n, -1);
  for (std::size_t u = 0; u < n; ++u) {
    j.names[u] = jointName(m, j.ids[u]);
    j.coulomb[u] = numericOr(m, "exoid_fc_" + j.names[u], 0.0);
    j.dofadr[u] = m->jnt_dofadr[j.ids[u]];
    j.qposadr[u] = m->jnt_qposadr[j.ids[u]];
    for (int a = 0; a < m->nu; ++a) {
      if (m->actuator_trntype[a] == mjTRN_JOINT && m->actuator_trnid[2 * a] == j.ids[u]) j.actuator[u] = a;
    }
  }
  return j;
}

// Locked joints: no excitation, and a rotor inertia that lets the lock carry their load.
void lockJoints(ChainSimConfig& config, const DrivenJoints& joints, mjModel* m) {
  for (const std::string& name : config.locked) {
    const auto it = std::find(joints.names.begin(), joints.names.end(), name);
    if (it == joints.names.end()) {
      const std::string all = core::joined(joints.names);
      throw std::invalid_argument("chain simulation: cannot lock joint '" + name + "': '" + config.model_path + "' drives " + all);
    }
    const auto i = static_cast<Eigen::Index>(it - joints.names.begin());
    config.trajectory.b_rad.col(i).setZero();
    config.trajectory.a_rad.col(i).setZero();
    m->dof_armature[joints.dofAdr(static_cast<int>(i))] += kLockInertia_kgm2;
  }
}

// The reference inside every joint's range: a limit's constraint force is no motor torque.
void checkReferenceInRange(const ChainSimConfig& config, const SerialChain& chain) {
  Eigen::VectorXd q, qd, qdd;
  const auto n = static_cast<Eigen::Index>(std::llround(config.duration_s / config.dt_s));
  for (Eigen::Index k = 0; k < n; ++k) {
    config.trajectory.at(static_cast<double>(k) * config.dt_s, q, qd, qdd);
    for (int i = 0; i < config.trajectory.dof(); ++i) {
      const ChainLinkBody& l = chain.links[static_cast<std::size_t>(i)];
      if (q[i] < l.q_min_rad || q[i] > l.q_max_rad) {
        throw std::invalid_argument("chain simulation: the trajectory takes joint '" + l.joint + "' to " + std::to_string(q[i]) +
                                    " rad at t = " + std::to_string(static_cast<double>(k) * config.dt_s) + " s, outside its range [" +
                                    std::to_string(l.q_min_rad) + ", " + std::to_string(l.q_max_rad) + "] rad in '" + config.model_path + "'");
      }
    }
  }
}

// Integration substeps: the smoothed Coulomb term is a damper of fc / v0 near zero velocity,
// with time constant I / (fc / v0) (0.2 ms on leg3's ankle); explicit RK4 at 1 ms would ring
// there (its stability ends at h |lambda| ~ 2.8), chattering at every velocity reversal. So the
// plant advances in substeps with h |lambda| <= 1; control and recording stay at 1 / dt.
// `M` is the joint-space inertia at the start.
int integrationSubsteps(const ChainSimConfig& config, const DrivenJoints& joints, const std::vector<mjtNum>& M, int nv, double v0) {
  int substeps = 1;
  for (int i = 0; i < joints.dof() && v0 > 0.0; ++i) {
    const int a = joints.dofAdr(i);
    const double lambda = joints.coulomb[static_cast<std::size_t>(i)] / v0 / M[static_cast<std::size_t>(a * nv + a)];
    substeps = std::max(substeps, static_cast<int>(std::ceil(lambda * config.dt_s)));
  }
  // The motor's first-order lag is resolved too: 2 pi f_a h <= 0.25 per substep.
  substeps = std::max(substeps, static_cast<int>(std::ceil(kTwoPi * config.actuator_bandwidth_hz * config.dt_s / 0.25)));
  return std::min(substeps, 50);
}

// The table's columns (see ChainSimResult::table).
std::vector<std::string> chainColumns(const std::vector<std::string>& names, bool record_derivatives, bool mounted) {
  std::vector<std::string> columns{"t"};
  for (const char* prefix : {"q_", "tau_"}) {
    for (const std::string& j : names) columns.push_back(prefix + j);
  }
  if (record_derivatives) {
    for (const char* prefix : {"qd_", "qdd_"}) {
      for (const std::string& j : names) columns.push_back(prefix + j);
    }
  }
  for (const char* prefix : {"q_", "qd_", "qdd_", "tau_"}) {
    for (const std::string& j : names) columns.push_back(prefix + j + "_true");
  }
  for (const std::string& j : names) columns.push_back("q_" + j + "_ref");
  if (mounted) {
    for (const char* c : {"base_acc_x", "base_acc_z", "base_gyro_y"}) columns.emplace_back(c);
    if (record_derivatives) columns.emplace_back("base_alpha_y");
    for (const char* c : {"base_x", "base_z", "base_pitch"}) columns.emplace_back(c);
  }
  return columns;
}

// The rig running: the plant (d), the controller's inverse dynamics (dr), the sensors and the
// motors' lag. One call of sample() per row of the table.
class ChainRig {
 public:
  ChainRig(mjModel* m, const DrivenJoints& joints, const ChainSimConfig& config)
      : m_(m), joints_(joints), config_(config), dof_(joints.dof()), data_(makeData(m)), ref_data_(makeData(m)), d_(data_.get()),
        dr_(ref_data_.get()), v0_(config.coulomb_v0_radps), sensors_(config.sensors, joints.dof(), config.seed, config.dt_s),
        base_body_(chainBaseBody(m, m->jnt_bodyid[joints.ids.front()])), motor_(dof_), command_(dof_), tau_read_(dof_) {}

  bool mounted() const { return !joints_.mount.empty(); }

  // At rest on the reference at t = 0; PD gains from the joint-space inertia there, each joint a
  // second-order loop at bandwidth_hz, damping ratio 0.7; the substeps per sample. Returns them.
  int start() {
    config_.trajectory.at(0.0, q_ref_, qd_ref_, qdd_ref_);
    for (int i = 0; i < dof_; ++i) {
      d_->qpos[joints_.qposAdr(i)] = q_ref_[i];
      d_->qvel[joints_.dofAdr(i)] = qd_ref_[i];
    }
    mj_forward(m_, d_);
    // A mount's springs pre-loaded so that the base starts in static equilibrium (as the APAL
    // leg's pedestal): at rest, spring = bias force on each mount coordinate.
    for (const int k : joints_.mount) {
      const double stiffness = m_->jnt_stiffness[k];
      if (stiffness > 0.0) m_->qpos_spring[m_->jnt_qposadr[k]] = d_->qfrc_bias[m_->jnt_dofadr[k]] / stiffness;
    }
    if (mounted()) {
      mj_forward(m_, d_);
      base_rest_p_ = Eigen::Map<const Eigen::Vector3d>(d_->xpos + 3 * base_body_);
      base_rest_R_ = baseRotation();
    }
    std::vector<mjtNum> M(static_cast<std::size_t>(m_->nv) * static_cast<std::size_t>(m_->nv));
    mj_fullM(m_, M.data(), d_->qM);
    substeps_ = integrationSubsteps(config_, joints_, M, m_->nv, v0_);
    m_->opt.timestep = config_.dt_s / substeps_;
    core::PidGains& g = gains_;
    g.kp_Nm_per_rad.resize(dof_);
    g.kd_Nms_per_rad.resize(dof_);
    g.derivative = core::DerivativeSource::kMeasuredVelocity;
    g.derivative_cutoff_Hz = 0.0;
    g.integral_limit_Nm = config_.integral_limit_Nm;
    const double wn = kTwoPi * config_.bandwidth_hz;
    for (int i = 0; i < dof_; ++i) {
      const int a = joints_.dofAdr(i);
      const double inertia = M[static_cast<std::size_t>(a * m_->nv + a)];
      g.kp_Nm_per_rad[i] = inertia * wn * wn;
      g.kd_Nms_per_rad[i] = 2.0 * 0.7 * wn * inertia;
    }
    g.ki_Nm_per_rad_s = g.kp_Nm_per_rad * (kTwoPi * config_.integral_hz);
    pid_.emplace(g, config_.dt_s);
    // The motor torque: a first-order lag behind the command (actuator_bandwidth_hz; 0 = the
    // command at once, a staircase), so the torque is continuous in time like a real drive's and
    // row k's torque is the one acting at t_k.
    const double h = config_.dt_s / substeps_;
    lag_ = config_.actuator_bandwidth_hz > 0.0 ? 1.0 - std::exp(-kTwoPi * config_.actuator_bandwidth_hz * h) : 1.0;
    return substeps_;
  }

  // Row k of the table: readings, command, the state and torque at t_k; then the plant advanced to t_k+1.
  void sample(Eigen::Index k, Table& table) {
    const double t = static_cast<double>(k) * config_.dt_s;
    config_.trajectory.at(t, q_ref_, qd_ref_, qdd_ref_);
    read();
    control();
    // At rest on the reference at t = 0 with the feedforward's holding torque: no start transient
    // (without the feedforward the feedback starts from zero torque and sags at first).
    if (k == 0 || config_.actuator_bandwidth_hz <= 0.0) motor_ = command_;
    if (k == 0) sensors_.resetTorqueFilters(motor_);  // the torque sensors read the holding torque from the start
    // 3.-4. the row: state, acceleration and joint torque at t_k
    applyTorque();
    mj_forward(m_, d_);
    checkStepHealth(m_, d_, t, "mj_forward");
    record(k, t, table);
    tracking_ss_ += (q_ - q_ref_).squaredNorm();
    advance(t);
  }

  const core::PidGains& gains() const { return gains_; }
  double trackingRms(Eigen::Index n) const { return std::sqrt(tracking_ss_ / static_cast<double>(std::max<Eigen::Index>(1, n * dof_))); }

 private:
  double friction(int i, double qd) const {
    const double fc = joints_.coulomb[static_cast<std::size_t>(i)];
    return v0_ > 0.0 ? fc * std::tanh(qd / v0_) : fc * static_cast<double>((qd > 0.0) - (qd < 0.0));
  }

  // 1. readings: the exact state, and the encoder's angles (noise, quantisation)
  void read() {
    q_.resize(dof_);
    qd_.resize(dof_);
    q_read_.resize(dof_);
    for (int i = 0; i < dof_; ++i) {
      q_[i] = d_->qpos[joints_.qposAdr(i)];
      qd_[i] = d_->qvel[joints_.dofAdr(i)];
    }
    sensors_.angles(q_, q_read_);
  }

  // 2. controller: inverse dynamics at the reference and Coulomb (the feedforward), PID on the readings
  void control() {
    if (!config_.feedforward) {
      command_.setZero();
      pid_->update(q_ref_, qd_ref_, q_read_, qd_, command_);
      return;
    }
    for (int i = 0; i < dof_; ++i) {
      dr_->qpos[joints_.qposAdr(i)] = q_ref_[i];
      dr_->qvel[joints_.dofAdr(i)] = qd_ref_[i];
      dr_->qacc[joints_.dofAdr(i)] = qdd_ref_[i];
    }
    mj_inverse(m_, dr_);
    for (int i = 0; i < dof_; ++i) {
      command_[i] = dr_->qfrc_inverse[joints_.dofAdr(i)] + friction(i, qd_ref_[i]);
    }
    pid_->update(q_ref_, qd_ref_, q_read_, qd_, command_);
  }

  void applyTorque() {
    for (int i = 0; i < dof_; ++i) {
      const int a = joints_.actuator[static_cast<std::size_t>(i)];
      d_->ctrl[a] = motor_[i] / m_->actuator_gear[6 * a];
      d_->qfrc_applied[joints_.dofAdr(i)] = -friction(i, d_->qvel[joints_.dofAdr(i)]);  // the plant's Coulomb friction
    }
  }

  void record(Eigen::Index k, double t, Table& table) {
    Eigen::Index c = 0;
    table.values(k, c++) = t;
    for (int i = 0; i < dof_; ++i) table.values(k, c++) = q_read_[i];
    Eigen::VectorXd tau(dof_), qdd(dof_);
    for (int i = 0; i < dof_; ++i) {
      tau[i] = d_->qfrc_actuator[joints_.dofAdr(i)];
      qdd[i] = d_->qacc[joints_.dofAdr(i)];
    }
    sensors_.torques(tau, tau_read_);
    for (int i = 0; i < dof_; ++i) table.values(k, c++) = tau_read_[i];
    if (config_.record_derivatives) {
      for (int i = 0; i < dof_; ++i) table.values(k, c++) = qd_[i];
      for (int i = 0; i < dof_; ++i) table.values(k, c++) = qdd[i];
    }
    for (const Eigen::VectorXd* v : {&q_, &qd_, &qdd, &tau}) {
      for (int i = 0; i < dof_; ++i) table.values(k, c++) = (*v)[i];
    }
    for (int i = 0; i < dof_; ++i) table.values(k, c++) = q_ref_[i];
    if (!mounted()) return;
    // The base IMU at the chain's base frame (chainBaseBody: the stand): MuJoCo's
    // accelerometer and gyro there (specific force and rate, in that frame), with their noise;
    // then the frame's exact displacement and pitch from rest.
    mj_rnePostConstraint(m_, d_);
    mjtNum acc[6], vel[6];
    mj_objectAcceleration(m_, d_, mjOBJ_XBODY, base_body_, acc, 1);
    mj_objectVelocity(m_, d_, mjOBJ_XBODY, base_body_, vel, 1);
    const Eigen::Vector3d imu = sensors_.imu(Eigen::Vector3d(acc[3], acc[5], vel[1]));
    for (int i = 0; i < 3; ++i) table.values(k, c++) = imu[i];
    if (config_.record_derivatives) table.values(k, c++) = acc[1];  // the pitch acceleration, exact
    const Eigen::Vector3d p = base_rest_R_.transpose() * (Eigen::Map<const Eigen::Vector3d>(d_->xpos + 3 * base_body_) - base_rest_p_);
    const Eigen::Matrix3d R = base_rest_R_.transpose() * baseRotation();
    table.values(k, c++) = p.x();
    table.values(k, c++) = p.z();
    table.values(k, c++) = std::atan2(R(0, 2), R(0, 0));
  }

  Eigen::Matrix3d baseRotation() const {
    return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(d_->xmat + 9 * base_body_);
  }

  // Advance to t_k+1 in substeps: friction follows the velocity, the motor the command.
  void advance(double t) {
    for (int sub = 0; sub < substeps_; ++sub) {
      if (sub > 0) {
        applyTorque();
        mj_forward(m_, d_);
      }
      integrateStep(m_, d_);
      checkStepHealth(m_, d_, t, "integration");
      motor_ += lag_ * (command_ - motor_);
    }
  }

  mjModel* m_;
  const DrivenJoints& joints_;
  const ChainSimConfig& config_;
  int dof_;
  DataPtr data_, ref_data_;
  mjData* d_;
  mjData* dr_;
  double v0_;
  Sensors sensors_;
  int base_body_;
  Eigen::Vector3d base_rest_p_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d base_rest_R_ = Eigen::Matrix3d::Identity();
  int substeps_ = 1;
  core::PidGains gains_;
  std::optional<core::PidController> pid_;
  double lag_ = 1.0;
  Eigen::VectorXd motor_, command_, tau_read_;
  Eigen::VectorXd q_ref_, qd_ref_, qdd_ref_, q_, qd_, q_read_;
  double tracking_ss_ = 0.0;
};

}  // namespace

bool hasCompliantMount(const std::string& model_path) {
  if (isUrdfFile(model_path)) return true;  // simulated on the stand (urdf_rig.hpp)
  const ModelPtr model = loadMjcfFile(model_path);
  return !drivenJoints(model.get(), model_path).mount.empty();
}

ChainSimResult simulateChain(const ChainSimConfig& config_in) {
  config_in.validate();
  ChainSimResult r;
  r.config = config_in;
  ChainSimConfig& config = r.config;
  const ModelPtr model = loadChainRig(config);
  mjModel* m = model.get();
  m->opt.timestep = config.dt_s;
  // The joints' ranges are the design's limits, checked on the reference below; as MuJoCo
  // constraints they would push back (a force no motor applied, missing from every recorded
  // torque) whenever the tracked state grazes a range the reference touches: off.
  m->opt.disableflags |= mjDSBL_LIMIT;
  const DrivenJoints joints = drivenJoints(m, config.model_path);
  if (config.vibration_level > 0.0) {
    if (joints.mount.empty()) {
      throw std::invalid_argument("chain simulation: vibration_level > 0 needs a compliant mount, but '" + config.model_path +
                                  "' has no joint between the world and the chain (the MJCF's <joint class=\"mount\" .../>, as "
                                  "models/leg3.xml's pedestal)");
    }
    const double L = config.vibration_level;  // natural frequencies / L, the same damping ratio
    for (const int k : joints.mount) {
      m->jnt_stiffness[k] /= L * L;
      m->dof_damping[m->jnt_dofadr[k]] /= L;
    }
  }
  r.chain = serialChainFromMjcf(m, joints.ids, joints.coulomb, config.model_path);
  r.chain.name = m->nnames > 0 && m->names[0] ? m->names : config.model_path;
  if (config.trajectory.dof() == 0) config.trajectory = defaultChainTrajectory(r.chain, config.seed);
  if (config.trajectory.dof() != joints.dof()) {
    throw std::invalid_argument("chain simulation: the trajectory has " + std::to_string(config.trajectory.dof()) + " joints, '" +
                                config.model_path + "' drives " + std::to_string(joints.dof()));
  }
  lockJoints(config, joints, m);  // after r.chain: the truth keeps the real rotor inertia
  checkReferenceInRange(config, r.chain);
  if (config.coulomb_v0_radps < 0.0) config.coulomb_v0_radps = numericOr(m, "exoid_coulomb_v0", 2e-3);
  r.mujoco_version = mj_versionString();

  ChainRig rig(m, joints, config);
  r.substeps = rig.start();
  const auto n = static_cast<Eigen::Index>(std::llround(config.duration_s / config.dt_s));
  r.table.names = chainColumns(joints.names, config.record_derivatives, !joints.mount.empty());
  r.table.values.resize(n, static_cast<Eigen::Index>(r.table.names.size()));
  for (Eigen::Index k = 0; k < n; ++k) rig.sample(k, r.table);
  r.tracking_rms_rad = rig.trackingRms(n);
  r.kp_Nm_per_rad = rig.gains().kp_Nm_per_rad;
  r.ki_Nm_per_rad_s = rig.gains().ki_Nm_per_rad_s;
  r.kd_Nms_per_rad = rig.gains().kd_Nms_per_rad;
  // The controller as IDIM-IV reads it (a real rig's comes from a --controller file instead).
  const auto list = [](const Eigen::VectorXd& v) {
    std::string out;
    char buf[32];
    for (Eigen::Index i = 0; i < v.size(); ++i) {
      std::snprintf(buf, sizeof buf, "%.17g", v[i]);
      out += (i ? "," : "") + std::string(buf);
    }
    return out;
  };
  char bw[32];
  std::snprintf(bw, sizeof bw, "%.17g", config.actuator_bandwidth_hz);
  r.table.metadata = {{"exoid", "chain simulation"},
                      {"model", r.chain.name},
                      {"model_path", config.model_path},
                      {"chain_selection", config.selection.label()},
                      {"seed", std::to_string(config.seed)},
                      {"mujoco", r.mujoco_version},
                      {"controller_kp_Nm_per_rad", list(r.kp_Nm_per_rad)},
                      {"controller_kd_Nms_per_rad", list(r.kd_Nms_per_rad)},
                      {"controller_law", config.integral_hz > 0.0 ? "pid_measured_velocity" : "pd_measured_velocity"},
                      {"feedforward", config.feedforward ? "true" : "false"},
                      {"actuator_bandwidth_Hz", bw},
                      {"vibration_level", std::to_string(config.vibration_level)}};
  if (config.integral_hz > 0.0) {
    std::snprintf(bw, sizeof bw, "%.17g", config.integral_limit_Nm);
    r.table.metadata.emplace_back("controller_ki_Nm_per_rad_s", list(r.ki_Nm_per_rad_s));
    r.table.metadata.emplace_back("controller_integral_limit_Nm", bw);
  }
  if (config.sensors.encoder_backlash_deg > 0.0) r.table.metadata.emplace_back("encoder_backlash_deg", std::to_string(config.sensors.encoder_backlash_deg));
  if (!config.locked.empty()) {
    std::string locked;
    for (const std::string& j : config.locked) locked += (locked.empty() ? "" : ",") + j;
    r.table.metadata.emplace_back("locked_joints", locked);
  }
  return r;
}

}  // namespace exoid::sim
