// `exoid simulate` and `exoid truth`.
#include "exoid/core/atomic_file.hpp"
#include "exoid/core/format.hpp"
#include "exoid/experiments/commands/commands.hpp"
#include "exoid/experiments/commands/robot_commands.hpp"
#include "exoid/experiments/commands/simulate_request.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/experiments/protocol/sim_bridge.hpp"
#include "exoid/experiments/report/table.hpp"
#include "exoid/sim/serial_chain.hpp"
#include "exoid/sim/sidecar.hpp"
#include "exoid/sim/truth.hpp"

#include <iostream>
#include <memory>
#include <variant>

namespace exoid::experiments {

namespace {

void runSimulate(const SimulateRequest& request, const std::string& out) {
  const std::variant<sim::SimConfig, sim::ChainSimConfig> rig = simulationOf(request);
  if (const auto* chain = std::get_if<sim::ChainSimConfig>(&rig)) return simulateChainToFiles(*chain, out);
  const sim::SimConfig& config = std::get<sim::SimConfig>(rig);
  core::checkOutputWritable(out);  // before the simulation, not after it
  core::checkOutputWritable(sim::sidecarPathOf(out));
  const sim::SimResult r = sim::simulate(config);
  const ident::Dataset d = toDataset(r);
  const nlohmann::json side = simulationSidecar(r, d);
  sim::writeCsv(r, out);
  const std::string json_path = sim::sidecarPathOf(out);
  writeJsonFile(json_path, side);
  const auto& s = r.stats;
  std::cout << "wrote " << out << " (" << r.table.rows() << " samples) and " << json_path << "\n"
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
  const bool urdf = sim::isUrdfFile(path);
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
  struct Args {
    SimulateRequest request;
    std::string out;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "simulate",
      "Simulate a leg in MuJoCo at 1 kHz (PID tracking, sensor noise, a vibrating stand) and write the\n"
      "dataset CSV plus a JSON sidecar (same name, .json) with every setting, the seed, versions and\n"
      "the truths. The APAL leg (default): its four-bar and pedestal, the truths of its rigid links,\n"
      "lumped four-bar band and best fit. Any other chain (--model leg3|FILE, an MJCF with motors or a\n"
      "URDF, a tree's chain by --base/--tip/--lock): the motor rig, its standard and base parameters.");
  addSimulateOptions(*cmd, args->request);
  cmd->add_option("--out", args->out, "Dataset CSV to write")->required();
  cmd->callback([args] { runSimulate(args->request, args->out); });
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
