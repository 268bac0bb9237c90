// `exoid simulate` and `exoid truth`.
#include "exoid/core/atomic_file.hpp"
#include "exoid/core/format.hpp"
#include "exoid/experiments/commands/robot_commands.hpp"
#include "exoid/experiments/protocol/excitation_io.hpp"
#include "exoid/experiments/commands/commands.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/experiments/protocol/sim_bridge.hpp"
#include "exoid/experiments/report/table.hpp"
#include "exoid/sim/serial_chain.hpp"
#include "exoid/sim/sidecar.hpp"
#include "exoid/sim/truth.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>

namespace exoid::experiments {

namespace {

struct SimulateArgs {
  sim::SimConfig config;
  std::string out;
  bool record_derivatives = false;  ///< chain models: exact qd_, qdd_ columns
  double coulomb_v0_radps = -1.0;   ///< chain models: Coulomb smoothing (< 0: the model's)
  double bandwidth_hz = 4.0;        ///< chain models: PD bandwidth
  // Every leg's rig, one spelling (the APAL leg's own options stay its aliases):
  std::vector<std::string> lock;    ///< joints locked (segmental records); the APAL leg: hip (--lock-hip)
  core::ChainSelection selection;   ///< a URDF tree's chain: --base, --tip, --lock JOINT=VALUE
  double integral_hz = 0.0;         ///< the feedback's integral, ki = kp 2 pi f (0 = PD); given or not: cmd->count
  std::vector<double> tau_bias_Nm;  ///< torque sensor bias per joint (the APAL leg: --tau-bias-hip, --tau-bias-knee)
  double actuator_bandwidth_hz = 0.0;  ///< every joint's (the APAL leg: --hip/--knee-actuator-bandwidth)
  CLI::App* cmd = nullptr;
  bool given(const char* option) const { return cmd->count(option) > 0; }
};

// --lock names each joint once.
void checkLockedOnce(const SimulateArgs& a) {
  for (std::size_t k = 0; k < a.lock.size(); ++k) {
    if (std::find(a.lock.begin(), a.lock.begin() + static_cast<std::ptrdiff_t>(k), a.lock[k]) != a.lock.begin() + static_cast<std::ptrdiff_t>(k)) {
      throw CLI::ValidationError("--lock", "names " + a.lock[k] + " twice");
    }
  }
}

// --tau-bias: one value per joint of the robot.
std::vector<double> tauBias(const SimulateArgs& a, std::size_t joints) {
  if (a.tau_bias_Nm.size() != joints) {
    throw CLI::ValidationError("--tau-bias", "expected one bias per joint (" + core::toText(joints) + "), got " + core::toText(a.tau_bias_Nm.size()));
  }
  return a.tau_bias_Nm;
}

// --excitation's design for a robot with these joints (in order); refused naming the option.
sim::NamedTrajectory excitationFor(const SimulateArgs& a, const std::vector<std::string>& joints) {
  try {
    return readExcitationFile(a.cmd->get_option("--excitation")->as<std::string>(), joints);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError("--excitation", e.what());
  }
}

// A model other than the APAL leg: the serial-chain simulator. The APAL rig's own options (its
// pedestal, four-bar, actuators, paper trajectories) do not apply and are refused by name.
void runChainSimulate(const SimulateArgs& a) {
  for (const char* apal_only :
       {"--trajectory", "--fourier-hip", "--fourier-knee", "--fourier-f0", "--lock-hip", "--ramp", "--tau-bias-hip", "--tau-bias-knee",
        "--floor-force", "--floor-force-z", "--floor-frequency", "--floor-random", "--cylinder-mass-scale", "--fc-hip", "--fv-hip",
        "--fc-knee", "--fv-knee", "--knee-armature", "--hip-actuator-bandwidth", "--knee-actuator-bandwidth", "--no-exact"}) {
    if (a.cmd->count(apal_only) > 0) {
      throw CLI::ValidationError(apal_only, std::string("is an option of the APAL leg's rig; '") + a.config.model_path +
                                                "' runs on the serial-chain simulator (see exoid simulate --help, groups 'Rig (every "
                                                "leg)' and 'Chain models')");
    }
  }
  sim::ChainSimConfig c = chainSimConfig(a.config);
  if (!a.selection.empty() && !sim::isUrdfPath(c.model_path)) {
    throw CLI::ValidationError("--base/--tip/--lock JOINT=VALUE", "choose a chain out of a URDF's tree; '" + c.model_path +
                                                                   "' is an MJCF, simulated as it is (its motors' joints)");
  }
  c.selection = a.selection;
  // The chain's joints, read from the file once when an option is checked against them.
  std::vector<std::string> joints;
  if (a.given("--tau-bias") || a.given("--excitation")) joints = sim::serialChainFromFile(c.model_path, c.selection).jointNames();
  if (a.given("--tau-bias")) c.sensors.tau_bias_Nm = tauBias(a, joints.size());
  if (a.given("--actuator-bandwidth")) c.actuator_bandwidth_hz = a.actuator_bandwidth_hz;
  if (a.cmd->count("--torque-sensor-bandwidth") > 0) c.sensors.tau_bandwidth_Hz = a.config.sensors.tau_bandwidth_Hz;
  c.coulomb_v0_radps = a.coulomb_v0_radps;
  c.bandwidth_hz = a.bandwidth_hz;
  c.integral_hz = a.integral_hz;
  c.record_derivatives = a.record_derivatives;
  if (a.integral_hz >= a.bandwidth_hz) {
    throw CLI::ValidationError("--integral-hz", "must lie below the position loop's bandwidth (--bandwidth " + fmt(a.bandwidth_hz) + " Hz)");
  }
  c.locked = a.lock;
  c.seed = a.config.seed;
  if (a.given("--excitation")) {
    // The design's joints must be the chain's, in order; the joints it holds are the rig's locks.
    const sim::NamedTrajectory design = excitationFor(a, joints);
    c.trajectory = design.series;
    for (std::size_t k = 0; k < static_cast<std::size_t>(design.series.locked_joints); ++k) {
      if (std::find(c.locked.begin(), c.locked.end(), joints[k]) == c.locked.end()) c.locked.push_back(joints[k]);
    }
  }
  simulateChainToFiles(c, a.out);
}

// The APAL leg's settings with every leg's rig options applied (its own spellings are aliases).
sim::SimConfig apalRigOptions(const SimulateArgs& a) {
  sim::SimConfig c = a.config;
  const auto alias = [&a](const char* generic, std::initializer_list<const char*> own) {
    for (const char* o : own) {
      if (a.given(generic) && a.given(o)) throw CLI::ValidationError(generic, std::string("and ") + o + " set the same; give one");
    }
  };
  alias("--tau-bias", {"--tau-bias-hip", "--tau-bias-knee"});
  alias("--actuator-bandwidth", {"--hip-actuator-bandwidth", "--knee-actuator-bandwidth"});
  alias("--lock", {"--lock-hip"});
  if (a.given("--tau-bias")) c.sensors.tau_bias_Nm = tauBias(a, kLegJoints.size());
  if (a.given("--actuator-bandwidth")) c.actuators.hip_bandwidth_Hz = c.actuators.knee_bandwidth_Hz = a.actuator_bandwidth_hz;
  if (a.given("--integral-hz")) c.gains.ki_Nm_per_rad_s = c.gains.kp_Nm_per_rad * (2.0 * M_PI * a.integral_hz);
  if (a.given("--lock") && a.lock != std::vector<std::string>{"hip"}) {
    throw CLI::ValidationError("--lock", "the APAL leg's rig locks its hip alone (--lock hip), for the knee-only record");
  }
  for (const char* lock : {"--lock", "--lock-hip"}) {
    if (a.given(lock) && c.trajectory != 0) {
      throw CLI::ValidationError(lock, "holds a Fourier trajectory's or a design's hip at its offset (--fourier-hip/--fourier-knee "
                                       "or --excitation); the paper's knee-only record is --trajectory 1");
    }
  }
  if (a.given("--lock")) c.fourier.locked_joints = 1;
  return c;
}

void runSimulate(const SimulateArgs& a) {
  checkLockedOnce(a);
  if (!sim::isApalLegModel(a.config.model_path)) return runChainSimulate(a);
  if (!a.selection.empty()) {
    throw CLI::ValidationError("--base/--tip/--lock JOINT=VALUE", "choose a chain out of a URDF's tree; the APAL leg's rig is its own");
  }
  for (const char* chain_only : {"--record-derivatives", "--coulomb-v0", "--bandwidth"}) {
    if (a.cmd->count(chain_only) > 0) {
      throw CLI::ValidationError(chain_only, "is an option of the motor rig (--model leg3|FILE); the APAL leg's rig takes its PD "
                                             "gains from a sweep's [simulation] and writes its exact derivatives unless --no-exact");
    }
  }
  sim::SimConfig config = apalRigOptions(a);
  if (a.cmd->count("--excitation") > 0) excitationFor(a, kLegJoints);  // the design's joints must be the leg's
  core::checkOutputWritable(a.out);  // before the simulation, not after it
  core::checkOutputWritable(sim::sidecarPathOf(a.out));
  const sim::SimResult r = sim::simulate(config);
  const ident::Dataset d = toDataset(r);
  const nlohmann::json side = simulationSidecar(r, d);
  sim::writeCsv(r, a.out);
  const std::string json_path = sim::sidecarPathOf(a.out);
  writeJsonFile(json_path, side);
  const auto& s = r.stats;
  std::cout << "wrote " << a.out << " (" << r.table.rows() << " samples) and " << json_path << "\n"
            << "tracking error RMS hip " << fmt(s.tracking_hip.rms_deg, 3) << " deg, knee "
            << fmt(s.tracking_knee.rms_deg, 3) << " deg; loop error max " << fmt(s.loop_error_max_m, 3)
            << " m; pedestal |x| max " << fmt(s.base_x_max_abs_m, 3) << " m; " << fmt(s.wall_time_s, 3) << " s\n";
  const nlohmann::json& hf = side.at("torque_variance_above_10Hz");
  std::cout << "torque variance above 10 Hz (Welch): recorded hip " << fixed(100.0 * hf.at("tau_hip").get<double>(), 2)
            << " %, knee " << fixed(100.0 * hf.at("tau_knee").get<double>(), 2) << " %";
  if (hf.contains("tau_hip_ideal")) {
    std::cout << "; ideal at the exact states hip " << fixed(100.0 * hf.at("tau_hip_ideal").get<double>(), 2)
              << " %, knee " << fixed(100.0 * hf.at("tau_knee_ideal").get<double>(), 2) << " %";
  }
  std::cout << "\n";
}

struct TruthArgs {
  std::string model, urdf, json_out;
  core::ChainSelection selection;
  sim::ModelVariant variant;
};

void runTruth(TruthArgs a) {
  if (!a.model.empty() && !a.urdf.empty()) {
    throw CLI::ValidationError("truth", "give the robot once: --model FILE (--urdf is its alias), not both");
  }
  // --model names a robot as every command does (MJCF or URDF); --urdf is kept as its alias.
  const std::string path = !a.urdf.empty() ? a.urdf : !a.model.empty() ? a.model : sim::defaultModelPath();
  const bool urdf = !endsWith(path, ".xml");
  // Another robot than the APAL leg: its chain's truth (standard and base parameters). X is the
  // 2-link leg's (hip, knee); any other chain gets its own parameters, never X of two of its joints.
  if (!a.selection.empty() || (!urdf && !sim::isApalLegModel(path))) return truthOfChain(path, a.json_out, a.selection);
  if (urdf) {
    const sim::SerialChain chain = sim::serialChainFromUrdf(path);
    if (chain.links.size() != 2 || chain.links[0].joint != "hip" || chain.links[1].joint != "knee") return truthOfChain(path, a.json_out);
  }
  if (!a.json_out.empty()) core::checkOutputWritable(a.json_out);
  const sim::Truth t = urdf ? sim::truthFromUrdf(path) : sim::rigidTruth(sim::loadLeg(path, a.variant, true));
  TextTable table({"param", "unit", "value"});
  for (int i = 0; i < sim::kNumParams; ++i) {
    table.addRow({sim::paramNames()[static_cast<std::size_t>(i)], sim::paramUnits()[static_cast<std::size_t>(i)],
                  fmt(t.x[static_cast<std::size_t>(i)], 8)});
  }
  std::cout << "X of the rigid links of " << path << " (Lt = " << t.thigh_length_m
            << " m, g = " << t.gravity_mps2 << " m/s^2):\n";
  table.print(std::cout);
  if (!a.json_out.empty()) {
    writeJsonFile(a.json_out, {{"tool", toolJson()},
                               {"source", t.source},
                               {"parameters", paramsJson(toParamVector(t.x))},
                               {"thigh_length_m", t.thigh_length_m},
                               {"gravity_mps2", t.gravity_mps2}});
  }
}

}  // namespace

void addSimulateCommand(CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "simulate",
      "Simulate a leg in MuJoCo at 1 kHz (PID tracking, sensor noise, a vibrating stand) and write the\n"
      "dataset CSV plus a JSON sidecar (same name, .json) with every setting, the seed, versions and\n"
      "the truths. The APAL leg (default): its four-bar and pedestal, the truths of its rigid links,\n"
      "lumped four-bar band and best fit. Any other chain (--model leg3|FILE, an MJCF with motors or a\n"
      "URDF, a tree's chain by --base/--tip/--lock): the motor rig, its standard and base parameters.");
  addSimOptions(*cmd, args->config);
  cmd->add_option("--seed", args->config.seed, "Seed of the sensor noise and floor disturbance")->check(seedValidator())->capture_default_str();
  cmd->add_flag("!--no-exact", args->config.exact_columns, "Omit the exact (ground-truth) columns");
  cmd->add_option("--out", args->out, "Dataset CSV to write")->required();
  cmd->add_flag("--record-derivatives", args->record_derivatives,
                "Chain models: also write qd_<joint>, qdd_<joint>, the exact derivatives (a rig that logs them)")
      ->group("Chain models");
  cmd->add_option("--coulomb-v0", args->coulomb_v0_radps,
                  "Chain models: Coulomb friction -fc tanh(qd / v0), rad/s; 0 = -fc sgn(qd), the regressor's own shape "
                  "(default: the model's exoid_coulomb_v0)")
      ->check(CLI::NonNegativeNumber)->group("Chain models");
  cmd->add_option("--bandwidth", args->bandwidth_hz, "Chain models: PD tracking bandwidth per joint, Hz")
      ->check(positiveNumber())->capture_default_str()->group("Chain models");
  const char* rig = "Rig (every leg)";
  cmd->add_option_function<std::vector<std::string>>(
         "--lock",
         [args](const std::vector<std::string>& locks) {
           for (const std::string& l : locks) {
             if (l.find('=') == std::string::npos) {
               args->lock.push_back(l);
             } else {
               addTreeLock(args->selection, l);
             }
           }
         },
         "Joints locked at the trajectory's offset, e.g. --lock hip,knee for a chain's ankle record (their recorded\n"
         "torque is the motor's holding command; identify --stage leaves it out); the APAL leg: hip (= --lock-hip).\n"
         "JOINT=VALUE: a URDF tree's joint held at VALUE (rad), off the chain, as identify's --lock (group 'Robot')")
      ->delimiter(',')->group(rig);
  cmd->add_option("--integral-hz", args->integral_hz,
                  "The feedback's integral, ki = kp 2 pi f per joint (0 = PD), written to the record's controller metadata,\n"
                  "which IDIM-IV reads. Default: a chain's 0, below its --bandwidth; the APAL leg's gains' own ki (about\n"
                  "0.5 Hz), which this replaces")
      ->check(CLI::NonNegativeNumber)->group(rig);
  cmd->add_option("--tau-bias", args->tau_bias_Nm,
                  "Torque sensor bias, N m, one per joint (comma-separated; the APAL leg: = --tau-bias-hip, --tau-bias-knee)")
      ->delimiter(',')->group(rig);
  cmd->add_option("--actuator-bandwidth", args->actuator_bandwidth_hz,
                  "Every joint's actuator: the torque follows the command through a first-order lag of this bandwidth, Hz (0 =\n"
                  "ideal; default: the APAL leg's motor and hydraulics, 100 Hz on a chain); --feedforward/--no-feedforward, in\n"
                  "'Simulation', apply to every leg too")
      ->check(CLI::NonNegativeNumber)->group(rig);
  addChainSelectionOptions(*cmd, args->selection, false);
  args->cmd = cmd;
  cmd->callback([args] { runSimulate(*args); });
}

void addTruthCommand(CLI::App& app) {
  auto args = std::make_shared<TruthArgs>();
  CLI::App* cmd = app.add_subcommand("truth", "Print X of the rigid links of an MJCF model or a URDF (default: the built-in leg).");
  cmd->add_option("--model", args->model,
                  "The robot: apal (default), leg3, or an MJCF (.xml) or URDF file; for a robot other than the APAL\n"
                  "leg, its standard and base parameters (as identify --model fits them)")
      ->transform([](const std::string& s) { return sim::modelPathFor(s); })
      ->check(CLI::ExistingFile);
  cmd->add_option("--urdf", args->urdf, "The same as --model (kept for older scripts)")->check(CLI::ExistingFile);
  addChainSelectionOptions(*cmd, args->selection);
  cmd->add_option("--fc-hip", args->variant.fc_hip_Nm, "Override hip Coulomb friction, N m");
  cmd->add_option("--fv-hip", args->variant.fv_hip_Nms, "Override hip viscous friction, N m s/rad");
  cmd->add_option("--fc-knee", args->variant.fc_knee_Nm, "Override knee Coulomb friction, N m");
  cmd->add_option("--fv-knee", args->variant.fv_knee_Nms, "Override knee viscous friction, N m s/rad");
  cmd->add_option("--json", args->json_out, "Also write {\"parameters\": {...}} here");
  cmd->callback([args] { runTruth(*args); });
}

}  // namespace exoid::experiments
