#include "exoid/experiments/protocol/sim_bridge.hpp"
#include "exoid/experiments/commands/robot_commands.hpp"

#include "exoid/core/format.hpp"
#include "exoid/experiments/protocol/excitation_io.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/experiments/version.hpp"
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/estimators/segmental.hpp"
#include "exoid/ident/signals/spectrum.hpp"
#include "exoid/sim/sidecar.hpp"

#include <cmath>
#include <sstream>

namespace exoid::experiments {

ident::Dataset toDataset(const sim::SimResult& r) {
  const sim::Table& t = r.table;
  ident::Dataset d;
  for (const auto& [key, value] : t.metadata) d.comments.push_back(" " + key + ": " + value);
  const Eigen::Index n = t.values.rows();
  d.t_s = t.col("t");
  d.q_rad.resize(n, 2);
  d.tau_Nm.resize(n, 2);
  d.q_rad << t.col("q_hip"), t.col("q_knee");
  d.tau_Nm << t.col("tau_hip"), t.col("tau_knee");
  const std::vector<std::string> required{"t", "q_hip", "q_knee", "tau_hip", "tau_knee"};
  for (const std::string& name : t.names) {
    if (std::find(required.begin(), required.end(), name) == required.end()) d.extra_names.push_back(name);
  }
  d.extra.resize(n, static_cast<Eigen::Index>(d.extra_names.size()));
  for (std::size_t k = 0; k < d.extra_names.size(); ++k) d.extra.col(static_cast<Eigen::Index>(k)) = t.col(d.extra_names[k]);
  return d;
}

ident::JointSignals exactSignals(const ident::Dataset& d, const std::string& tau_suffix) {
  ident::JointSignals s;
  const Eigen::Index n = d.size();
  s.t_s = d.t_s;
  auto pair = [&](const std::string& a, const std::string& b) {
    Eigen::MatrixX2d m(n, 2);
    m << d.extraColumn(a), d.extraColumn(b);
    return m;
  };
  s.q_rad = pair("q_hip_true", "q_knee_true");
  s.qd_radps = pair("qd_hip_true", "qd_knee_true");
  s.qdd_radps2 = pair("qdd_hip_true", "qdd_knee_true");
  s.tau_Nm = pair("tau_hip_" + tau_suffix, "tau_knee_" + tau_suffix);
  return s;
}

ident::ParamVector toParamVector(const sim::ParamArray& x) {
  return Eigen::Map<const ident::ParamVector>(x.data());
}

ident::LegConstants constantsOf(const sim::Truth& t) { return {t.thigh_length_m, t.gravity_mps2}; }

BestFit bestFitTruth(const ident::Dataset& d, const ident::LegConstants& c, const ident::ParamVector& fallback) {
  const ident::JointSignals s = exactSignals(d, "ideal");
  BestFit b;
  b.x = fallback;
  // Knee block from the knee equation; thigh block from the hip equation minus the knee part: the
  // segmental strategy's two stages on the one record.
  const ident::Robot robot = ident::twoLinkLeg(c);
  const ident::RecordRows rows = ident::recordRows(robot, s);
  const ident::SegmentalPlan plan(robot, {1, 0});
  const ident::StageProblem knee = plan.problem(0, rows, {});
  const ident::LsResult lk = ident::solveLeastSquares(knee.H, knee.y);
  if (lk.summary.status == ident::Status::kConverged) {
    b.x.segment<ident::kGroupSize>(ident::kShankFirst) = lk.x;
  } else {
    for (int i = ident::kShankFirst; i < ident::kShankFirst + ident::kGroupSize; ++i) b.from_fallback.emplace_back(ident::paramName(i));
  }
  const ident::StageProblem hip = plan.problem(1, rows, {b.x.segment<ident::kGroupSize>(ident::kShankFirst)});
  const ident::LsResult lh = ident::solveLeastSquares(hip.H, hip.y);
  if (lh.summary.status == ident::Status::kConverged) {
    b.x.segment<ident::kGroupSize>(ident::kThighFirst) = lh.x;
  } else {
    for (int i = ident::kThighFirst; i < ident::kThighFirst + ident::kGroupSize; ++i) b.from_fallback.emplace_back(ident::paramName(i));
  }
  const Eigen::MatrixX2d pred = ident::predictTorque(s, b.x, c);
  b.residual_rms_Nm = std::sqrt((pred - s.tau_Nm).squaredNorm() / static_cast<double>(2 * s.size()));
  return b;
}

std::map<std::string, double> torqueVarianceAbove(const ident::Dataset& d, double f_hz) {
  const double fs = 1.0 / d.sampleInterval_s();
  std::map<std::string, double> out;
  out["tau_hip"] = ident::varianceFractionAbove(d.tau_Nm.col(0), fs, f_hz);
  out["tau_knee"] = ident::varianceFractionAbove(d.tau_Nm.col(1), fs, f_hz);
  for (const std::string& name : d.extra_names) {
    if (name.rfind("tau_", 0) == 0 && name.find("_cmd") == std::string::npos) {
      out[name] = ident::varianceFractionAbove(d.extraColumn(name), fs, f_hz);
    }
  }
  return out;
}

nlohmann::json simulationSidecar(const sim::SimResult& r, const ident::Dataset& d) {
  nlohmann::json j = sim::sidecar(r, std::string(kVersion) + " (" + kGitRevision + ")");
  j["tool"] = toolJson();
  const ident::ParamVector rigid = toParamVector(r.truth.x);
  // Each truth is {"parameters": {...}, ...} so `exoid identify --truth` reads every one of them.
  if (r.config.exact_columns) {
    const BestFit b = bestFitTruth(d, constantsOf(r.truth), rigid);
    j["truth"]["best_fit"] = {{"parameters", paramsJson(b.x)},
                              {"residual_rms_Nm", b.residual_rms_Nm},
                              {"from_rigid", b.from_fallback},
                              {"description", "LS fit of the 2-link model to the exact, noise-free, vibration-free "
                                          "(ideal) torques at the exact states of this record: the best any "
                                          "estimator of this model can do on it. Blocks this record cannot "
                                          "identify are copied from the rigid truth (from_rigid). The 10-parameter "
                                          "model's: with a knee armature (knee_armature.Ia2 > 0) its Js absorbs "
                                          "the armature; compare identify --knee-armature with rigid and Ia2."}};
  }
  j["torque_variance_above_10Hz"] = torqueVarianceAbove(d);
  j["torque_variance_above_10Hz"]["method"] =
      "Welch (Hann, 2 s segments, 50 % overlap, mean removed): share of the variance above 10 Hz";
  return j;
}

namespace {
// "offset,a1,b1,a2,b2,..." in degrees -> joint j of a Fourier series in radians (the other
// joint's harmonics padded with zeros to the longer of the two).
void setFourierJoint(core::FourierSeries& f, int j, const std::vector<double>& deg, const char* flag) {
  if (deg.empty() || deg.size() % 2 == 0) {
    throw CLI::ValidationError(flag, "expected offset,a1,b1[,a2,b2...] in degrees (an odd count), got " +
                                         core::toText(deg.size()) + " values");
  }
  const double rad = M_PI / 180.0;
  const auto n = static_cast<Eigen::Index>(deg.size() / 2);
  if (n > f.harmonics()) {
    f.a_rad.conservativeResizeLike(Eigen::MatrixXd::Zero(n, 2));
    f.b_rad.conservativeResizeLike(Eigen::MatrixXd::Zero(n, 2));
  }
  f.a_rad.col(j).setZero();
  f.b_rad.col(j).setZero();
  f.offset_rad[j] = deg[0] * rad;
  for (Eigen::Index k = 0; k < n; ++k) {
    f.a_rad(k, j) = deg[static_cast<std::size_t>(2 * k + 1)] * rad;
    f.b_rad(k, j) = deg[static_cast<std::size_t>(2 * k + 2)] * rad;
  }
}
void addTrajectoryOptions(CLI::App& app, sim::SimConfig& c) {
  const char* g = "Simulation";
  CLI::Option* traj = app.add_option("--trajectory", c.trajectory, "Paper Table 1 trajectory 1-4")
                          ->check(CLI::Range(1, 4))->capture_default_str()->group(g);
  // A general finite Fourier series instead: q(t) = offset + sum_k a_k cos(2 pi k f0 t) + b_k sin(...).
  CLI::Option* fh = app.add_option_function<std::vector<double>>(
                           "--fourier-hip", [&c](const std::vector<double>& v) { setFourierJoint(c.fourier, 0, v, "--fourier-hip"); c.trajectory = 0; },
                           "Fourier trajectory, hip: offset,a1,b1,a2,b2,... in deg (replaces --trajectory)")
                       ->delimiter(',')->group(g);
  CLI::Option* fk = app.add_option_function<std::vector<double>>(
                           "--fourier-knee", [&c](const std::vector<double>& v) { setFourierJoint(c.fourier, 1, v, "--fourier-knee"); c.trajectory = 0; },
                           "Fourier trajectory, knee: offset,a1,b1,a2,b2,... in deg (replaces --trajectory)")
                       ->delimiter(',')->group(g);
  app.add_option("--fourier-f0", c.fourier.f0_hz, "Fourier base frequency, Hz")->check(positiveNumber())->capture_default_str()->group(g);
  app.add_flag_callback("--lock-hip", [&c] { c.fourier.locked_joints = 1; }, "Fourier trajectory: hold the hip at its offset with the rig's lock")->group(g);
  CLI::Option* ex = app.add_option_function<std::string>(
                           "--excitation",
                           [&c](const std::string& path) {
                             // Any robot's design: the command checks its joints against the model's.
                             c.fourier = readExcitationFile(path).series;
                             c.trajectory = 0;
                           },
                           "Excitation design JSON from `exoid excite` (replaces --trajectory)")
                       ->check(CLI::ExistingFile)->group(g);
  traj->excludes(fh);
  traj->excludes(fk);
  traj->excludes(ex);
  ex->excludes(fh);
  ex->excludes(fk);
}

}  // namespace

ident::Controller controllerOf(const sim::SimConfig& cfg, bool hip_locked) {
  ident::Controller c;
  c.kp_Nm_per_rad = cfg.gains.kp_Nm_per_rad;
  c.ki_Nm_per_rad_s = cfg.gains.ki_Nm_per_rad_s;
  c.kd_Nms_per_rad = cfg.gains.kd_Nms_per_rad;
  c.derivative_cutoff_hz = cfg.gains.derivative_cutoff_Hz;
  c.integral_limit_Nm = cfg.gains.integral_limit_Nm;
  c.feedforward = cfg.feedforward ? ident::Feedforward::kModel : ident::Feedforward::kNone;
  c.locked = {hip_locked, false};
  return c;
}

void addSimOptions(CLI::App& app, sim::SimConfig& c, bool choose_trajectory) {
  const char* g = "Simulation";
  if (choose_trajectory) addTrajectoryOptions(app, c);
  app.add_option("--duration", c.duration_s, "Recorded duration, s")->check(positiveNumber())->capture_default_str()->group(g);
  app.add_option("--ramp", c.ramp_s, "Smooth start ramp, s (run before recording)")->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--noise-q-deg", c.sensors.noise_q_deg, "Encoder noise std, deg")->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--quantisation-deg", c.sensors.quantisation_deg, "Encoder resolution, deg (0 = none)")->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--encoder-backlash-deg", c.sensors.encoder_backlash_deg,
                 "Play between each joint and its encoder, deg (a motor-side encoder behind a gear's backlash: angle motion "
                 "the torque does not drive; the controller reads it too); 0 = none")
      ->check(CLI::Range(0.0, 89.999))->capture_default_str()->group(g);
  app.add_option("--noise-tau", c.sensors.noise_tau_Nm, "Torque sensor noise std, N m")->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  c.sensors.tau_bias_Nm.resize(2, 0.0);  // hip, knee: the options below write into them
  app.add_option("--tau-bias-hip", c.sensors.tau_bias_Nm[0], "Torque sensor bias, hip, N m")->capture_default_str()->group(g);
  app.add_option("--tau-bias-knee", c.sensors.tau_bias_Nm[1], "Torque sensor bias, knee, N m")->capture_default_str()->group(g);
  app.add_option("--vibration", c.variant.vibration_level, "The stand's mount compliance level (0 = rigid, 1 = nominal; the APAL leg's pedestal, a chain's stand)")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--floor-force", c.floor.force_x_amplitude_N, "Floor disturbance: fore-aft sinusoidal force amplitude on the pedestal, N")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--floor-force-z", c.floor.force_z_amplitude_N, "Floor disturbance: vertical force amplitude, N")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--floor-frequency", c.floor.frequency_Hz, "Floor disturbance frequency, Hz")->check(positiveNumber())->capture_default_str()->group(g);
  app.add_option("--floor-random", c.floor.random_std_N, "Floor disturbance: white force std, N")->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--cylinder-mass-scale", c.variant.cylinder_mass_scale, "Scale of the cylinder and rod masses (0 = 2-link model exact)")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--fc-hip", c.variant.fc_hip_Nm, "Hip Coulomb friction, N m (default: model)")->check(CLI::NonNegativeNumber)->group(g);
  app.add_option("--fv-hip", c.variant.fv_hip_Nms, "Hip viscous friction, N m s/rad (default: model)")->check(CLI::NonNegativeNumber)->group(g);
  app.add_option("--fc-knee", c.variant.fc_knee_Nm, "Knee Coulomb friction, N m (default: model)")->check(CLI::NonNegativeNumber)->group(g);
  app.add_option("--fv-knee", c.variant.fv_knee_Nms, "Knee viscous friction, N m s/rad (default: model)")->check(CLI::NonNegativeNumber)->group(g);
  app.add_option("--knee-armature", c.variant.knee_armature_kgm2,
                 "Knee armature (reflected rotor/actuator inertia on the knee's diagonal), kg m^2 (default: model, 0); "
                 "the truth reports it as Ia2")
      ->check(CLI::NonNegativeNumber)->group(g);
  app.add_flag("--feedforward,!--no-feedforward", c.feedforward,
               "Model-based feedforward of the planned reference through the actuators' inverse (default on)")
      ->capture_default_str()->group(g);
  app.add_option("--hip-actuator-bandwidth", c.actuators.hip_bandwidth_Hz, "Hip motor torque bandwidth, Hz (0 = ideal)")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--knee-actuator-bandwidth", c.actuators.knee_bandwidth_Hz, "Knee hydraulic force-loop bandwidth, Hz (0 = ideal)")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--torque-sensor-bandwidth", c.sensors.tau_bandwidth_Hz, "Torque sensor anti-aliasing bandwidth, Hz (0 = ideal)")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--imu-acc-noise", c.sensors.imu_acc_noise_mps2, "Pedestal accelerometer noise std, m/s^2")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--imu-gyro-noise", c.sensors.imu_gyro_noise_radps, "Pedestal gyro noise std, rad/s")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--model", c.model_path,
                 "MJCF model: apal (the built-in APAL leg), leg3 (the built-in hip-knee-ankle leg) or a file; a model other "
                 "than the APAL leg (its <mujoco model=\"apal_leg\">) runs on the serial-chain simulator")
      ->transform([](const std::string& s) { return sim::modelPathFor(s); })
      ->check(CLI::ExistingFile)
      ->capture_default_str()
      ->group(g);
}

}  // namespace exoid::experiments
