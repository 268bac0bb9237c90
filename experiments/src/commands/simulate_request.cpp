#include "exoid/experiments/commands/simulate_request.hpp"

#include "exoid/core/format.hpp"
#include "exoid/experiments/commands/robot_commands.hpp"
#include "exoid/experiments/protocol/excitation_io.hpp"
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/experiments/protocol/sim_bridge.hpp"
#include "exoid/experiments/report/table.hpp"
#include "exoid/sim/serial_chain.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>

namespace exoid::experiments {

namespace {

// --lock names each joint once.
void checkLockedOnce(const SimulateRequest& a) {
  for (std::size_t k = 0; k < a.lock.size(); ++k) {
    if (std::find(a.lock.begin(), a.lock.begin() + static_cast<std::ptrdiff_t>(k), a.lock[k]) != a.lock.begin() + static_cast<std::ptrdiff_t>(k)) {
      throw CLI::ValidationError("--lock", "names " + a.lock[k] + " twice");
    }
  }
}

// --tau-bias: one value per joint of the robot.
std::vector<double> tauBias(const SimulateRequest& a, std::size_t joints) {
  if (a.tau_bias_Nm.size() != joints) {
    throw CLI::ValidationError("--tau-bias", "expected one bias per joint (" + core::toText(joints) + "), got " + core::toText(a.tau_bias_Nm.size()));
  }
  return a.tau_bias_Nm;
}

// --excitation's design for a robot with these joints (in order); refused naming the option.
sim::NamedTrajectory excitationFor(const SimulateRequest& a, const std::vector<std::string>& joints) {
  try {
    return readExcitationFile(a.cmd->get_option("--excitation")->as<std::string>(), joints);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError("--excitation", e.what());
  }
}

// A model other than the APAL leg: the serial-chain simulator. The APAL rig's own options (its
// pedestal, four-bar, actuators, paper trajectories) do not apply and are refused by name.
sim::ChainSimConfig chainRig(const SimulateRequest& a) {
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
  checkTreeSelection(a.selection, c.model_path);
  c.selection = a.selection;
  // The chain's joints, read from the file once when an option is checked against them.
  std::vector<std::string> joints;
  if (a.given("--tau-bias") || a.given("--excitation")) joints = sim::serialChainFromFile(c.model_path, c.selection).jointNames();
  if (a.given("--tau-bias")) c.sensors.tau_bias_Nm = tauBias(a, joints.size());
  if (a.given("--actuator-bandwidth")) c.actuator_bandwidth_hz = a.actuator_bandwidth_hz;
  if (a.given("--torque-sensor-bandwidth")) c.sensors.tau_bandwidth_Hz = a.config.sensors.tau_bandwidth_Hz;
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
  return c;
}

// The APAL leg's settings with every leg's rig options applied (its own spellings are aliases).
sim::SimConfig apalRig(const SimulateRequest& a) {
  for (const char* chain_only : {"--record-derivatives", "--coulomb-v0", "--bandwidth"}) {
    if (a.given(chain_only)) {
      throw CLI::ValidationError(chain_only, "is an option of the motor rig (--model leg3|FILE); the APAL leg's rig takes its PD "
                                             "gains from a sweep's [simulation] and writes its exact derivatives unless --no-exact");
    }
  }
  checkTreeSelection(a.selection, a.config.model_path);
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
  if (a.given("--excitation")) excitationFor(a, kLegJoints);  // the design's joints must be the leg's
  return c;
}

}  // namespace

void checkTreeSelection(const core::ChainSelection& selection, const std::string& model_path) {
  if (selection.empty() || sim::isUrdfFile(model_path)) return;
  const std::string what = sim::isApalLegModel(model_path) ? "the APAL leg's rig is its own"
                                                            : "'" + model_path + "' is an MJCF, simulated as it is (its motors' joints)";
  throw CLI::ValidationError("--base/--tip/--lock JOINT=VALUE", "choose a chain out of a URDF's tree; " + what);
}

std::variant<sim::SimConfig, sim::ChainSimConfig> simulationOf(const SimulateRequest& a) {
  checkLockedOnce(a);
  if (sim::isApalLegModel(a.config.model_path)) return apalRig(a);
  return chainRig(a);
}

void addSimulateOptions(CLI::App& cmd, SimulateRequest& r) {
  r.cmd = &cmd;
  addSimOptions(cmd, r.config);
  cmd.add_option("--seed", r.config.seed, "Seed of the sensor noise and floor disturbance")->check(seedValidator())->capture_default_str();
  cmd.add_flag("!--no-exact", r.config.exact_columns, "Omit the exact (ground-truth) columns");
  cmd.add_flag("--record-derivatives", r.record_derivatives,
               "Chain models: also write qd_<joint>, qdd_<joint>, the exact derivatives (a rig that logs them)")
      ->group("Chain models");
  cmd.add_option("--coulomb-v0", r.coulomb_v0_radps,
                 "Chain models: Coulomb friction -fc tanh(qd / v0), rad/s; 0 = -fc sgn(qd), the regressor's own shape "
                 "(default: the model's exoid_coulomb_v0)")
      ->check(CLI::NonNegativeNumber)->group("Chain models");
  cmd.add_option("--bandwidth", r.bandwidth_hz, "Chain models: PD tracking bandwidth per joint, Hz")
      ->check(positiveNumber())->capture_default_str()->group("Chain models");
  const char* rig = "Rig (every leg)";
  cmd.add_option_function<std::vector<std::string>>(
         "--lock",
         [&r](const std::vector<std::string>& locks) {
           for (const std::string& l : locks) {
             if (l.find('=') == std::string::npos) {
               r.lock.push_back(l);
             } else {
               addTreeLock(r.selection, l);
             }
           }
         },
         "Joints locked at the trajectory's offset, e.g. --lock hip,knee for a chain's ankle record (their recorded\n"
         "torque is the motor's holding command; identify --stage leaves it out); the APAL leg: hip (= --lock-hip).\n"
         "JOINT=VALUE: a URDF tree's joint held at VALUE (rad), off the chain, as identify's --lock (group 'Robot')")
      ->delimiter(',')->group(rig);
  cmd.add_option("--integral-hz", r.integral_hz,
                 "The feedback's integral, ki = kp 2 pi f per joint (0 = PD), written to the record's controller metadata,\n"
                 "which IDIM-IV reads. Default: a chain's 0, below its --bandwidth; the APAL leg's gains' own ki (about\n"
                 "0.5 Hz), which this replaces")
      ->check(CLI::NonNegativeNumber)->group(rig);
  cmd.add_option("--tau-bias", r.tau_bias_Nm,
                 "Torque sensor bias, N m, one per joint (comma-separated; the APAL leg: = --tau-bias-hip, --tau-bias-knee)")
      ->delimiter(',')->group(rig);
  cmd.add_option("--actuator-bandwidth", r.actuator_bandwidth_hz,
                 "Every joint's actuator: the torque follows the command through a first-order lag of this bandwidth, Hz (0 =\n"
                 "ideal; default: the APAL leg's motor and hydraulics, 100 Hz on a chain); --feedforward/--no-feedforward, in\n"
                 "'Simulation', apply to every leg too")
      ->check(CLI::NonNegativeNumber)->group(rig);
  addChainSelectionOptions(cmd, r.selection, false);
}

}  // namespace exoid::experiments
