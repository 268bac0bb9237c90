#include "exoid/sim/chain_simulate.hpp"

#include "exoid/sim/model.hpp"
#include "exoid/sim/mujoco_hooks.hpp"
#include "exoid/sim/random.hpp"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace exoid::sim {

namespace {

constexpr double kTwoPi = 6.283185307179586;

std::string jointName(const mjModel* m, int j) {
  const char* n = mj_id2name(m, mjOBJ_JOINT, j);
  return n ? n : "joint" + std::to_string(j);
}

double numericOr(const mjModel* m, const std::string& name, double fallback) {
  const int id = mj_name2id(m, mjOBJ_NUMERIC, name.c_str());
  return id >= 0 && m->numeric_size[id] > 0 ? m->numeric_data[m->numeric_adr[id]] : fallback;
}

void integrate(const mjModel* m, mjData* d) {
  if (m->opt.integrator == mjINT_RK4) {
    mj_RungeKutta(m, d, 4);
  } else {
    mj_Euler(m, d);
  }
}

}  // namespace

void ChainFourier::reference(double t_s, Eigen::VectorXd& q, Eigen::VectorXd& qd, Eigen::VectorXd& qdd) const {
  q = offset_rad;
  qd.setZero(dof());
  qdd.setZero(dof());
  for (Eigen::Index k = 0; k < sin_rad.cols(); ++k) {
    const double w = kTwoPi * base_frequency_hz * static_cast<double>(k + 1);
    const double s = std::sin(w * t_s), c = std::cos(w * t_s);
    q += sin_rad.col(k) * s + cos_rad.col(k) * c;
    qd += w * (sin_rad.col(k) * c - cos_rad.col(k) * s);
    qdd -= w * w * (sin_rad.col(k) * s + cos_rad.col(k) * c);
  }
}

void ChainFourier::validate() const {
  if (!(base_frequency_hz > 0.0 && std::isfinite(base_frequency_hz))) throw std::invalid_argument("trajectory: 'base_frequency_hz' must be > 0");
  if (dof() < 1) throw std::invalid_argument("trajectory: no joints");
  if (sin_rad.rows() != dof() || cos_rad.rows() != dof() || sin_rad.cols() != cos_rad.cols()) {
    throw std::invalid_argument("trajectory: 'sin_rad' and 'cos_rad' must be joints x harmonics, one row per offset");
  }
  if (!offset_rad.allFinite() || !sin_rad.allFinite() || !cos_rad.allFinite()) throw std::invalid_argument("trajectory: a NaN or Inf coefficient");
}

ChainFourier defaultChainTrajectory(const SerialChain& chain, std::uint64_t seed) {
  const int dof = static_cast<int>(chain.links.size());
  if (dof < 1) throw std::invalid_argument("default trajectory: the chain has no joints");
  constexpr int kHarmonics = 5;
  Rng rng(core::deriveSeed(seed, 101));
  ChainFourier f;
  f.base_frequency_hz = 0.1;
  f.offset_rad = Eigen::VectorXd::Zero(dof);
  f.sin_rad.resize(dof, kHarmonics);
  f.cos_rad.resize(dof, kHarmonics);
  for (int j = 0; j < dof; ++j) {
    const ChainLinkBody& l = chain.links[static_cast<std::size_t>(j)];
    double amplitude = 0.6;
    if (std::isfinite(l.q_min_rad) && std::isfinite(l.q_max_rad)) {
      f.offset_rad[j] = 0.5 * (l.q_min_rad + l.q_max_rad);
      amplitude = std::min(amplitude, 0.35 * (l.q_max_rad - l.q_min_rad));
    }
    for (int k = 0; k < kHarmonics; ++k) {
      f.sin_rad(j, k) = rng.uniform(-1.0, 1.0);
      f.cos_rad(j, k) = rng.uniform(-1.0, 1.0);
    }
    // |q - offset| <= the sum of |coefficients| = amplitude.
    const double total = f.sin_rad.row(j).cwiseAbs().sum() + f.cos_rad.row(j).cwiseAbs().sum();
    f.sin_rad.row(j) *= amplitude / total;
    f.cos_rad.row(j) *= amplitude / total;
  }
  return f;
}

void ChainSimConfig::validate() const {
  auto need = [](bool ok, const char* field, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("chain simulation: '") + field + "' must be " + what);
  };
  need(!model_path.empty(), "model_path", "a model file");
  need(duration_s > 0.0 && std::isfinite(duration_s), "duration_s", "> 0");
  need(dt_s > 0.0 && dt_s <= 0.01, "dt_s", "in (0, 0.01]");
  need(encoder_noise_rad >= 0.0 && std::isfinite(encoder_noise_rad), "encoder_noise_rad", ">= 0");
  need(encoder_resolution_rad >= 0.0 && std::isfinite(encoder_resolution_rad), "encoder_resolution_rad", ">= 0");
  need(torque_noise_Nm >= 0.0 && std::isfinite(torque_noise_Nm), "torque_noise_Nm", ">= 0");
  need(std::isfinite(coulomb_v0_radps), "coulomb_v0_radps", "a number (< 0: the model's, 0: sgn)");
  need(bandwidth_hz > 0.0 && bandwidth_hz < 0.1 / dt_s, "bandwidth_hz", "in (0, 0.1 / dt_s)");
  need(actuator_bandwidth_hz >= 0.0 && std::isfinite(actuator_bandwidth_hz), "actuator_bandwidth_hz", ">= 0");
  if (trajectory.dof() > 0) trajectory.validate();
}

ChainSimResult simulateChain(const ChainSimConfig& config_in) {
  config_in.validate();
  ChainSimResult r;
  r.config = config_in;
  ChainSimConfig& config = r.config;
  const ModelPtr model = loadMjcfFile(config.model_path);
  mjModel* m = model.get();
  m->opt.timestep = config.dt_s;
  // The joints' ranges are the design's limits, checked on the reference below; as MuJoCo
  // constraints they would push back (a force no motor applied, missing from every recorded
  // torque) whenever the tracked state grazes a range the reference touches: off.
  m->opt.disableflags |= mjDSBL_LIMIT;
  const std::vector<int> joints = drivenHinges(m, config.model_path);
  const int dof = static_cast<int>(joints.size());
  if (m->nv != dof) {
    throw std::invalid_argument("chain simulation: '" + config.model_path + "' has " + std::to_string(m->nv) +
                                " degrees of freedom but its motors drive " + std::to_string(dof) +
                                " hinges: every joint must be driven (a passive joint or a free base is not a serial chain exoid simulates)");
  }
  std::vector<double> coulomb(static_cast<std::size_t>(dof));
  std::vector<std::string> names(static_cast<std::size_t>(dof));
  std::vector<int> dofadr(static_cast<std::size_t>(dof)), qposadr(static_cast<std::size_t>(dof)), actuator(static_cast<std::size_t>(dof), -1);
  for (int i = 0; i < dof; ++i) {
    const auto u = static_cast<std::size_t>(i);
    names[u] = jointName(m, joints[u]);
    coulomb[u] = numericOr(m, "exoid_fc_" + names[u], 0.0);
    dofadr[u] = m->jnt_dofadr[joints[u]];
    qposadr[u] = m->jnt_qposadr[joints[u]];
    for (int a = 0; a < m->nu; ++a) {
      if (m->actuator_trntype[a] == mjTRN_JOINT && m->actuator_trnid[2 * a] == joints[u]) actuator[u] = a;
    }
  }
  r.chain = serialChainFromMjcf(m, joints, coulomb, config.model_path);
  r.chain.name = m->nnames > 0 && m->names[0] ? m->names : config.model_path;
  if (config.trajectory.dof() == 0) config.trajectory = defaultChainTrajectory(r.chain, config.seed);
  if (config.trajectory.dof() != dof) {
    throw std::invalid_argument("chain simulation: the trajectory has " + std::to_string(config.trajectory.dof()) + " joints, '" +
                                config.model_path + "' drives " + std::to_string(dof));
  }
  for (const std::string& name : config.locked) {  // after r.chain: the truth keeps the real rotor inertia
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) {
      std::string all;
      for (const std::string& n : names) all += (all.empty() ? "" : ", ") + n;
      throw std::invalid_argument("chain simulation: cannot lock joint '" + name + "': '" + config.model_path + "' drives " + all);
    }
    const auto i = static_cast<Eigen::Index>(it - names.begin());
    config.trajectory.sin_rad.row(i).setZero();
    config.trajectory.cos_rad.row(i).setZero();
    m->dof_armature[dofadr[static_cast<std::size_t>(i)]] += kLockInertia_kgm2;
  }
  {  // The reference inside every joint's range: a limit's constraint force is no motor torque.
    Eigen::VectorXd q, qd, qdd;
    const auto n = static_cast<Eigen::Index>(std::llround(config.duration_s / config.dt_s));
    for (Eigen::Index k = 0; k < n; ++k) {
      config.trajectory.reference(static_cast<double>(k) * config.dt_s, q, qd, qdd);
      for (int i = 0; i < dof; ++i) {
        const ChainLinkBody& l = r.chain.links[static_cast<std::size_t>(i)];
        if (q[i] < l.q_min_rad || q[i] > l.q_max_rad) {
          throw std::invalid_argument("chain simulation: the trajectory takes joint '" + l.joint + "' to " + std::to_string(q[i]) +
                                      " rad at t = " + std::to_string(static_cast<double>(k) * config.dt_s) + " s, outside its range [" +
                                      std::to_string(l.q_min_rad) + ", " + std::to_string(l.q_max_rad) + "] rad in '" + config.model_path + "'");
        }
      }
    }
  }
  const double v0 = config.coulomb_v0_radps < 0.0 ? numericOr(m, "exoid_coulomb_v0", 2e-3) : config.coulomb_v0_radps;
  config.coulomb_v0_radps = v0;
  const auto friction = [&](int i, double qd) {
    const double fc = coulomb[static_cast<std::size_t>(i)];
    return v0 > 0.0 ? fc * std::tanh(qd / v0) : fc * static_cast<double>((qd > 0.0) - (qd < 0.0));
  };
  r.mujoco_version = mj_versionString();

  DataPtr data = makeData(m), ref_data = makeData(m);
  mjData* d = data.get();
  mjData* dr = ref_data.get();
  Eigen::VectorXd q_ref, qd_ref, qdd_ref;
  config.trajectory.reference(0.0, q_ref, qd_ref, qdd_ref);
  for (int i = 0; i < dof; ++i) {
    d->qpos[qposadr[static_cast<std::size_t>(i)]] = q_ref[i];
    d->qvel[dofadr[static_cast<std::size_t>(i)]] = qd_ref[i];
  }
  mj_forward(m, d);
  // PD gains from the joint-space inertia at the start: each joint a second-order loop at
  // bandwidth_hz, damping ratio 0.7.
  std::vector<mjtNum> M(static_cast<std::size_t>(m->nv) * static_cast<std::size_t>(m->nv));
  mj_fullM(m, M.data(), d->qM);
  // Integration substeps: the smoothed Coulomb term is a damper of fc / v0 near zero velocity,
  // with time constant I / (fc / v0) (0.2 ms on leg3's ankle); explicit RK4 at 1 ms would ring
  // there (its stability ends at h |lambda| ~ 2.8), chattering at every velocity reversal. So the
  // plant advances in substeps with h |lambda| <= 1; control and recording stay at 1 / dt.
  int substeps = 1;
  for (int i = 0; i < dof && v0 > 0.0; ++i) {
    const int a = dofadr[static_cast<std::size_t>(i)];
    const double lambda = coulomb[static_cast<std::size_t>(i)] / v0 / M[static_cast<std::size_t>(a * m->nv + a)];
    substeps = std::max(substeps, static_cast<int>(std::ceil(lambda * config.dt_s)));
  }
  // The motor's first-order lag is resolved too: 2 pi f_a h <= 0.25 per substep.
  substeps = std::max(substeps, static_cast<int>(std::ceil(kTwoPi * config.actuator_bandwidth_hz * config.dt_s / 0.25)));
  substeps = std::min(substeps, 50);
  r.substeps = substeps;
  m->opt.timestep = config.dt_s / substeps;
  Eigen::VectorXd kp(dof), kd(dof);
  const double wn = kTwoPi * config.bandwidth_hz;
  for (int i = 0; i < dof; ++i) {
    const int a = dofadr[static_cast<std::size_t>(i)];
    const double inertia = M[static_cast<std::size_t>(a * m->nv + a)];
    kp[i] = inertia * wn * wn;
    kd[i] = 2.0 * 0.7 * wn * inertia;
  }

  const auto n = static_cast<Eigen::Index>(std::llround(config.duration_s / config.dt_s));
  r.table.names.push_back("t");
  const std::vector<std::pair<const char*, const char*>> groups = {{"q_", ""}, {"tau_", ""}};
  for (const auto& [prefix, suffix] : groups) {
    for (const std::string& j : names) r.table.names.push_back(prefix + j + suffix);
  }
  if (config.record_derivatives) {
    for (const char* prefix : {"qd_", "qdd_"}) {
      for (const std::string& j : names) r.table.names.push_back(prefix + j);
    }
  }
  for (const char* prefix : {"q_", "qd_", "qdd_", "tau_"}) {
    for (const std::string& j : names) r.table.names.push_back(prefix + j + "_true");
  }
  for (const std::string& j : names) r.table.names.push_back("q_" + j + "_ref");
  r.table.values.resize(n, static_cast<Eigen::Index>(r.table.names.size()));

  Rng encoder(streamSeed(config.seed, kStreamEncoder)), torque_sensor(streamSeed(config.seed, kStreamTorque));
  // The motor torque: a first-order lag behind the command (actuator_bandwidth_hz; 0 = the
  // command at once, a staircase), so the torque is continuous in time like a real drive's and
  // row k's torque is the one acting at t_k.
  const double h = config.dt_s / substeps;
  const double lag = config.actuator_bandwidth_hz > 0.0 ? 1.0 - std::exp(-kTwoPi * config.actuator_bandwidth_hz * h) : 1.0;
  Eigen::VectorXd motor(dof), command(dof);
  bool first = true;
  double tracking_ss = 0.0;
  const auto applyTorque = [&](const Eigen::VectorXd& torque) {
    for (int i = 0; i < dof; ++i) {
      const auto u = static_cast<std::size_t>(i);
      const int a = actuator[u];
      d->ctrl[a] = torque[i] / m->actuator_gear[6 * a];
      d->qfrc_applied[dofadr[u]] = -friction(i, d->qvel[dofadr[u]]);  // the plant's Coulomb friction
    }
  };
  for (Eigen::Index k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * config.dt_s;
    config.trajectory.reference(t, q_ref, qd_ref, qdd_ref);
    // 1. readings
    Eigen::VectorXd q(dof), qd(dof), q_read(dof);
    for (int i = 0; i < dof; ++i) {
      q[i] = d->qpos[qposadr[static_cast<std::size_t>(i)]];
      qd[i] = d->qvel[dofadr[static_cast<std::size_t>(i)]];
      double reading = q[i] + config.encoder_noise_rad * encoder.normal();
      if (config.encoder_resolution_rad > 0.0) reading = config.encoder_resolution_rad * std::round(reading / config.encoder_resolution_rad);
      q_read[i] = reading;
    }
    // 2. controller: inverse dynamics at the reference, Coulomb, PD on the readings
    for (int i = 0; i < dof; ++i) {
      const auto u = static_cast<std::size_t>(i);
      dr->qpos[qposadr[u]] = q_ref[i];
      dr->qvel[dofadr[u]] = qd_ref[i];
      dr->qacc[dofadr[u]] = qdd_ref[i];
    }
    mj_inverse(m, dr);
    for (int i = 0; i < dof; ++i) {
      const auto u = static_cast<std::size_t>(i);
      command[i] = dr->qfrc_inverse[dofadr[u]] + friction(i, qd_ref[i]) + kp[i] * (q_ref[i] - q_read[i]) + kd[i] * (qd_ref[i] - qd[i]);
    }
    if (first || config.actuator_bandwidth_hz <= 0.0) motor = command;  // at rest on the reference at t = 0: no start transient
    first = false;
    // 3.-4. the row: state, acceleration and joint torque at t_k
    applyTorque(motor);
    mj_forward(m, d);
    checkStepHealth(m, d, t, "mj_forward");
    Eigen::Index c = 0;
    r.table.values(k, c++) = t;
    for (int i = 0; i < dof; ++i) r.table.values(k, c++) = q_read[i];
    Eigen::VectorXd tau(dof), qdd(dof);
    for (int i = 0; i < dof; ++i) {
      tau[i] = d->qfrc_actuator[dofadr[static_cast<std::size_t>(i)]];
      qdd[i] = d->qacc[dofadr[static_cast<std::size_t>(i)]];
    }
    for (int i = 0; i < dof; ++i) r.table.values(k, c++) = tau[i] + config.torque_noise_Nm * torque_sensor.normal();
    if (config.record_derivatives) {
      for (int i = 0; i < dof; ++i) r.table.values(k, c++) = qd[i];
      for (int i = 0; i < dof; ++i) r.table.values(k, c++) = qdd[i];
    }
    for (const Eigen::VectorXd* v : {&q, &qd, &qdd, &tau}) {
      for (int i = 0; i < dof; ++i) r.table.values(k, c++) = (*v)[i];
    }
    for (int i = 0; i < dof; ++i) r.table.values(k, c++) = q_ref[i];
    tracking_ss += (q - q_ref).squaredNorm();
    // Advance to t_k+1 in substeps: friction follows the velocity, the motor the command.
    for (int sub = 0; sub < substeps; ++sub) {
      if (sub > 0) {
        applyTorque(motor);
        mj_forward(m, d);
      }
      integrate(m, d);
      checkStepHealth(m, d, t, "integration");
      motor += lag * (command - motor);
    }
  }
  r.tracking_rms_rad = std::sqrt(tracking_ss / static_cast<double>(std::max<Eigen::Index>(1, n * dof)));
  r.table.metadata = {{"exoid", "chain simulation"},
                      {"model", r.chain.name},
                      {"model_path", config.model_path},
                      {"seed", std::to_string(config.seed)},
                      {"mujoco", r.mujoco_version}};
  return r;
}

}  // namespace exoid::sim
