#pragma once
// `exoid simulate`'s options and the rig they describe, one implementation for the command and for
// Python's exoid.simulate(): the APAL leg's rig or a chain's, every leg's rig options in one
// spelling, each option checked against the robot and refused by name.
#include "exoid/core/tree_selection.hpp"
#include "exoid/sim/motor_rig.hpp"
#include "exoid/sim/simulate.hpp"

#include <CLI/CLI.hpp>

#include <string>
#include <variant>
#include <vector>

namespace exoid::experiments {

struct SimulateRequest {
  sim::SimConfig config;              ///< the APAL rig's settings (and the model, noise, seed of every leg)
  bool record_derivatives = false;    ///< chain models: exact qd_, qdd_ columns
  double coulomb_v0_radps = -1.0;     ///< chain models: Coulomb smoothing (< 0: the model's)
  double bandwidth_hz = 4.0;          ///< chain models: PD bandwidth
  // Every leg's rig, one spelling (the APAL leg's own options stay its aliases):
  std::vector<std::string> lock;      ///< joints locked (segmental records); the APAL leg: hip (--lock-hip)
  core::ChainSelection selection;     ///< a URDF tree's chain: --base, --tip, --lock JOINT=VALUE
  double integral_hz = 0.0;           ///< the feedback's integral, ki = kp 2 pi f (0 = PD)
  std::vector<double> tau_bias_Nm;    ///< torque sensor bias per joint (the APAL leg: --tau-bias-hip, --tau-bias-knee)
  double actuator_bandwidth_hz = 0.0;  ///< every joint's (the APAL leg: --hip/--knee-actuator-bandwidth)
  const CLI::App* cmd = nullptr;      ///< where the options were parsed (which were given)
  bool given(const char* option) const { return cmd->count(option) > 0; }
};

/// --base, --tip and --lock JOINT=VALUE choose the simulated chain out of a URDF's tree: refused
/// (CLI::ValidationError) when given for the APAL leg's rig or an MJCF, which is simulated as it is.
void checkTreeSelection(const core::ChainSelection& selection, const std::string& model_path);

/// Every option of `exoid simulate` but --out, parsed into `r` (r.cmd = &cmd).
void addSimulateOptions(CLI::App& cmd, SimulateRequest& r);

/// The rig `r` describes: the APAL leg's (sim::SimConfig) or, for any other model, a chain's
/// (sim::ChainSimConfig). Throws CLI::ValidationError naming an option that does not apply to the
/// robot or does not fit it (a bias per joint, a design of its joints, ...).
std::variant<sim::SimConfig, sim::ChainSimConfig> simulationOf(const SimulateRequest& r);

}  // namespace exoid::experiments
