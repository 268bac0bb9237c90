// `exoid reproduce`: the README's main job.
#include "exoid/core/atomic_file.hpp"
#include "exoid/experiments/commands/robot_commands.hpp"
#include "exoid/experiments/commands/simulate_request.hpp"
#include "exoid/experiments/commands/commands.hpp"
#include "exoid/experiments/protocol/robot_reproduce.hpp"
#include "exoid/ident/design/excitation.hpp"
#include "exoid/experiments/protocol/excitation_io.hpp"
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/experiments/protocol/reproduce.hpp"
#include "exoid/experiments/protocol/sim_bridge.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/report/output_manifest.hpp"
#include "exoid/experiments/report/table.hpp"

#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

namespace exoid::experiments {

namespace {

struct Args {
  ProtocolConfig config = defaultReproduceConfig();
  ReproduceOutputs out = [] {
    ReproduceOutputs o;
    o.dir = "results/reproduce";
    return o;
  }();
  std::vector<std::string> variants;
  std::string knee_excitation = defaultKneeExcitationPath(), both_excitation = defaultBothExcitationPath();
  bool optimised_arm = true;
  bool keep_edits = false;
  int design_restarts = ident::ExcitationOptions{}.restarts;  ///< a chain's design (the APAL leg's are shipped)
  core::ChainSelection selection;  ///< a URDF tree's chain: --base, --tip, --lock
  CLI::App* cmd = nullptr;
};

// --model naming a robot other than the APAL leg: the chain protocol (robot_reproduce.hpp). The
// APAL rig's own options are refused by name, never ignored.
void runChain(const Args& a) {
  for (const CLI::Option* o : a.cmd->get_options()) {
    const std::string name = o->get_name();
    const bool chain_ok = name == "--model" || name == "--out" || name == "--no-plots" || name == "--plots" || name == "--seed" || name == "--keep-edits" ||
                          name == "--methods" || name == "--duration" || name == "--dt" || name == "--noise-q-deg" ||
                          name == "--quantisation-deg" || name == "--noise-tau" || name == "--help" || name == "--no-video" ||
                          name == "--design-restarts" || name == "--vibration" || name == "--encoder-backlash-deg" ||
                          name == "--torque-sensor-bandwidth" || name == "--imu-acc-noise" || name == "--imu-gyro-noise" ||
                          name == "--base" || name == "--tip" || name == "--lock";
    if (o->count() > 0 && !chain_ok) {
      throw CLI::ValidationError(name, "is not an option of the chain protocol (reproduce --model " + a.config.sim.model_path +
                                           "): it takes --out, --no-plots, --seed, --methods, --duration, --dt, --noise-q-deg, "
                                           "--quantisation-deg, --noise-tau, --encoder-backlash-deg, --vibration (a model with a "
                                           "mount), --torque-sensor-bandwidth, --imu-acc-noise, --imu-gyro-noise, --design-restarts, "
                                           "--base, --tip, --lock (a URDF tree's chain)");
    }
  }
  checkTreeSelection(a.selection, a.config.sim.model_path);
  ChainReproduceArgs c;
  c.out = a.out.dir;
  c.plots = a.out.plots;
  c.sim = chainSimConfig(a.config.sim);
  c.sim.selection = a.selection;
  // The chain's rig stands still and senses torque ideally unless asked (the APAL leg's reproduce
  // defaults are its pedestal's nominal vibration and its torque sensor's 200 Hz).
  if (a.cmd->count("--vibration") == 0) c.sim.vibration_level = 0.0;
  if (a.cmd->count("--torque-sensor-bandwidth") > 0) c.sim.sensors.tau_bandwidth_Hz = a.config.sim.sensors.tau_bandwidth_Hz;
  c.seed = a.config.seed;
  c.design_restarts = a.design_restarts;
  c.keep_edits = a.keep_edits;
  if (!a.variants.empty()) {
    c.methods.clear();
    for (const std::string& v : a.variants) {
      c.methods.push_back(ident::parseMethod(v));
    }
  }
  reproduceChain(c);
}

void run(Args a) {
  if (!sim::isApalLegModel(a.config.sim.model_path)) return runChain(a);
  checkTreeSelection(a.selection, a.config.sim.model_path);
  if (a.cmd->count("--design-restarts") > 0) {
    throw CLI::ValidationError("--design-restarts", "designs a chain's excitation (--model leg3|FILE); the APAL leg's designs are "
                               "--excitation-knee and --excitation-both");
  }
  if (!a.variants.empty()) {
    a.config.variants.clear();
    for (const std::string& v : a.variants) a.config.variants.push_back(parseVariant(v));
  }
  // The optimised arm: the same protocol and seed, identified on the designed records.
  ProtocolConfig optimised_config = a.config;
  if (a.optimised_arm) {
    optimised_config.knee_excitation = readExcitationFile(a.knee_excitation, kLegJoints).series;
    optimised_config.both_excitation = readExcitationFile(a.both_excitation, kLegJoints).series;
    optimised_config.validate();
  }
  core::prepareOutputFolder(a.out.dir);  // before the work, not after it
  startFolderRun(a.out.dir, a.keep_edits, std::cout);
  const auto started = std::filesystem::file_time_type::clock::now() - std::chrono::seconds(1);
  std::cout << "exoid reproduce: simulating trajectories 1-4 (" << a.config.sim.duration_s
            << " s each), identifying with " << a.config.variants.size() << " methods (G = "
            << a.config.methods.rls_pso.pso.max_iterations << ")...\n"
            << std::flush;
  const ProtocolResult r = runProtocol(a.config);
  std::optional<ProtocolResult> opt;
  if (a.optimised_arm) {
    std::cout << "optimised-excitation arm: identifying on the designed records (" << a.knee_excitation << ", "
              << a.both_excitation << "), validating on trajectories 2 and 4...\n"
              << std::flush;
    opt = runProtocol(optimised_config);
  }
  writeReproduceOutputs(r, a.out, opt ? &*opt : nullptr);
  finishFolderRun(a.out.dir, started, {{"command", "reproduce"}, {"seed", a.config.seed}, {"tool", toolJson()}});
  TextTable t({"method", "torque-space err hip", "knee", "worst param err", "knee val |e| (N m)", "hip val |e| (N m)", "time (s)"});
  for (const VariantScore& s : r.scores) {
    Eigen::Index w = 0;
    s.vs_best_fit.rel.cwiseAbs().maxCoeff(&w);
    t.addRow({toString(s.variant), fixed(100.0 * s.torque_space_vs_best_fit.hip, 2) + " %",
              fixed(100.0 * s.torque_space_vs_best_fit.knee, 2) + " %",
              std::string(ident::paramName(static_cast<int>(w))) + " " + fixed(100.0 * s.vs_best_fit.rel[w], 1) + " %",
              fixed(s.knee_validation.mean_abs, 4) + " +- " + fixed(s.knee_validation.std_abs, 4),
              fixed(s.hip_validation.mean_abs, 4) + " +- " + fixed(s.hip_validation.std_abs, 4), fmt(s.outcome.wallTime_s(), 3)});
  }
  t.print(std::cout);
  if (opt) {
    std::cout << "\noptimised-excitation arm (median |param error| vs best fit, paper's trajectories -> designed):\n";
    TextTable o({"method", "median |param err|", "torque-space err (mean of joints)", "knee val RMS (N m)", "hip val RMS (N m)"});
    for (std::size_t k = 0; k < r.scores.size(); ++k) {
      const VariantScore &p = r.scores[k], &d = opt->scores[k];
      o.addRow({toString(p.variant), fixed(100.0 * medianAbs(p.vs_best_fit.rel), 2) + " % -> " + fixed(100.0 * medianAbs(d.vs_best_fit.rel), 2) + " %",
                fixed(50.0 * (p.torque_space_vs_best_fit.hip + p.torque_space_vs_best_fit.knee), 2) + " % -> " +
                    fixed(50.0 * (d.torque_space_vs_best_fit.hip + d.torque_space_vs_best_fit.knee), 2) + " %",
                fixed(p.knee_validation.rms, 4) + " -> " + fixed(d.knee_validation.rms, 4),
                fixed(p.hip_validation.rms, 4) + " -> " + fixed(d.hip_validation.rms, 4)});
    }
    o.print(std::cout);
  }
  std::cout << '\n' << verdict(r) << "\n\nreport: " << a.out.dir << "/report.md (" << fmt(r.wall_time_s, 3) << " s)\n";
}

}  // namespace

void addReproduceCommand(CLI::App& app) {
  auto args = std::make_shared<Args>();
  std::string arms;  // every arm the protocol runs, from its own list (the help cannot fall behind it)
  for (Variant v : allVariants()) arms += (arms.empty() ? "" : ", ") + std::string(toString(v));
  CLI::App* cmd = app.add_subcommand(
      "reproduce",
      "Reproduce the paper on the simulated APAL leg with ground truth: simulate trajectories 1-4,\n"
      "process signals as the paper (forward differences, 10 Hz zero-phase filter), identify with\n"
      "the segmental strategy by each of its " + std::to_string(allVariants().size()) + " arms (" + arms + "),\n"
      "validate (knee on 2, hip on 4), and write report.md with figures. --model leg3 or a robot file:\n"
      "the same protocol on a serial chain.");
  cmd->add_option("--out", args->out.dir, "Results folder")->capture_default_str();
  cmd->add_flag("!--no-plots", args->out.plots, "Skip the figures (no python3-matplotlib needed)");
  cmd->add_flag("--keep-edits", args->keep_edits,
                "When --out holds a previous run whose outputs were changed by hand (complete.json keeps their sizes and "
                "SHA-256): refuse, naming them, instead of rewriting them");
  cmd->add_flag("!--no-video", args->out.media, "Skip the still and the clip of the leg (no OSMesa/ffmpeg needed)");
  cmd->add_flag("--clip-raw-torque", args->out.clip_raw_torque,
                "The clip's overlay: the raw recorded torque instead of the processed (filtered) one the methods fit");
  cmd->add_option("--design-restarts", args->design_restarts,
                  "--model (a chain): restarts of its excitation design (exoid excite --restarts)")
      ->check(CLI::Range(1, 1000))->capture_default_str();
  cmd->add_option("--methods", args->variants, "Subset of: ls, rls, pso, rls-pso, lad, ls-exact, ls-stacked, ls-parallel, idim-iv, ls-base, idim-iv-base, default (exoid identify's defaults)")->delimiter(',');
  cmd->add_flag("!--no-optimised-arm", args->optimised_arm,
                "Skip the optimised-excitation arm (the same protocol identified on designed records, validated on 2 and 4)");
  cmd->add_option("--excitation-knee", args->knee_excitation,
                  "Optimised arm: the designed record replacing trajectory 1 (exoid excite --knee-only)")
      ->check(CLI::ExistingFile)->capture_default_str();
  cmd->add_option("--excitation-both", args->both_excitation,
                  "Optimised arm: the designed record replacing trajectory 3 (exoid excite); validation stays on 2 and 4")
      ->check(CLI::ExistingFile)->capture_default_str();
  addSimOptions(*cmd, args->config.sim, /*choose_trajectory=*/false);  // the protocol runs 1-4
  addChainSelectionOptions(*cmd, args->selection);
  addSignalOptions(*cmd, args->config.signals);
  addMethodOptions(*cmd, args->config.methods);
  // One protocol seed instead of the PSO seed: sensor noise and PSO streams derive from it.
  cmd->remove_option(cmd->get_option("--seed"));
  cmd->add_option("--seed", args->config.seed, "Protocol seed (sensor noise of each record, PSO)")->check(seedValidator())->capture_default_str();
  args->cmd = cmd;
  cmd->callback([args] { run(*args); });
}

}  // namespace exoid::experiments
