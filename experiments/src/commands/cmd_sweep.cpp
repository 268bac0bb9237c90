// `exoid sweep` and `exoid merge`: the grid of conditions x seeds x methods, and its shards.
#include "exoid/experiments/commands/robot_commands.hpp"
#include "exoid/experiments/commands/commands.hpp"
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/experiments/sweep/sweep_config.hpp"
#include "exoid/experiments/sweep/sweep_runner.hpp"
#include "exoid/sim/data_dir.hpp"
#include "exoid/sim/model.hpp"

#include <iostream>
#include <memory>
#include <optional>

namespace exoid::experiments {

namespace {

struct SweepArgs {
  std::string config = sim::dataPath("configs/default_sweep.toml");
  CLI::Option* config_option = nullptr;
  std::string model;  ///< --model: replaces the config's [sweep] model
  SweepRunOptions run;
  std::optional<int> seeds;
  std::optional<std::uint64_t> master_seed;
  std::vector<std::string> methods;
  std::vector<double> noise_tau, noise_q, quantisation, vibration, cylinder, backlash;
  std::vector<std::string> trajectories;
  std::optional<double> duration_s;
  std::optional<long> pso_iterations;
  std::optional<ident::BaseTerms> base_terms;
  std::string shard;
};

void runSweepCommand(const SweepArgs& a) {
  std::string file = a.config;
  // --model naming a chain without --config: the chain's default grid.
  if (!a.model.empty() && a.config_option->count() == 0 && a.model != "apal" && !sim::isApalLegModel(sim::modelPathFor(a.model))) {
    file = sim::dataPath("configs/robot_sweep.toml");
  }
  SweepConfig c = loadSweepConfig(file, a.model);
  auto list = [&c](const std::vector<double>& v, std::vector<double>& target, const char* key, const char* flag) {
    if (v.empty()) return;
    target = v;
    c.origin[key] = flag;
  };
  list(a.noise_tau, c.torque_noise_Nm, "grid.torque_noise_Nm", "--noise-tau");
  list(a.noise_q, c.angle_noise_deg, "grid.angle_noise_deg", "--noise-q-deg");
  list(a.quantisation, c.quantisation_deg, "grid.quantisation_deg", "--quantisation-deg");
  list(a.vibration, c.vibration_level, "grid.vibration_level", "--vibration");
  list(a.cylinder, c.cylinder_mass_scale, "grid.cylinder_mass_scale", "--cylinder-mass-scale");
  list(a.backlash, c.encoder_backlash_deg, "grid.encoder_backlash_deg", "--encoder-backlash-deg");
  if (!a.trajectories.empty()) {
    c.trajectories = a.trajectories;
    c.origin["grid.trajectories"] = "--trajectories";
  }
  if (a.seeds) {
    c.seeds = *a.seeds;
    c.origin["sweep.seeds"] = "--seeds";
  }
  if (a.master_seed) {
    c.master_seed = *a.master_seed;
    c.origin["sweep.master_seed"] = "--master-seed";
  }
  if (!a.methods.empty()) c.setMethods(a.methods, "--methods");
  if (a.duration_s) c.base.sim.duration_s = *a.duration_s;
  if (a.pso_iterations) c.base.methods.rls_pso.pso.max_iterations = *a.pso_iterations;
  if (a.base_terms) {
    c.base.default_base_terms = *a.base_terms;
    c.origin["identification.base_terms"] = "--base-terms";
  }
  c.validate();
  SweepRunOptions o = a.run;
  if (!a.shard.empty()) {
    o.shard = parseShard(a.shard);
  } else if (const auto env = shardFromEnvironment()) {
    o.shard = *env;
  }
  runSweep(c, o, std::cout);
}

struct MergeArgs {
  std::string out;
  std::vector<std::string> shards;
  bool plots = true;
  bool keep_edits = false;
};

}  // namespace

void addSweepCommand(CLI::App& app) {
  auto a = std::make_shared<SweepArgs>();
  CLI::App* cmd = app.add_subcommand(
      "sweep",
      "Run the protocol (as `exoid reproduce`) over a grid of conditions (torque noise, angle noise and\n"
      "quantisation, vibration, cylinder mass) x seeds x methods, and summarise with 95 % CIs, paired\n"
      "Wilcoxon tests against LS and the Cramer-Rao bound. Resumable (same command again), shardable\n"
      "(--shard K/N or a Slurm array), deterministic for any thread count. See experiments/SWEEP.md.");
  a->config_option = cmd->add_option("--config", a->config, "Sweep TOML (with --model naming a chain: configs/robot_sweep.toml)")->capture_default_str();
  cmd->add_option("--model", a->model,
                  "[sweep] model: apal (the paper's protocol), leg3 or an MJCF file (any serial chain: its base parameters, "
                  "one fit per run; experiments/SWEEP.md)");
  cmd->add_option("--out", a->run.out, "Results folder (resumes when it holds the same sweep)")->capture_default_str();
  cmd->add_option("--threads", a->run.threads, "Worker threads (0 = all cores)")->check(CLI::NonNegativeNumber)->capture_default_str();
  cmd->add_option("--shard", a->shard, "Run shard K/N: cells with cell % N == K (default: from SLURM_ARRAY_TASK_ID/COUNT)");
  cmd->add_flag("!--no-plots", a->run.plots, "Skip the figures");
  cmd->add_flag("--keep-edits", a->run.keep_edits,
                "A finished folder whose outputs were changed after exoid wrote them (complete.json keeps their sizes and "
                "SHA-256): refuse, naming them, instead of rewriting them");
  const char* o = "Overrides of the config file";
  cmd->add_option("--seeds", a->seeds, "[sweep] seeds: replicates per cell, 1 to 1e6")->check(CLI::Range(1, 1000000))->group(o);
  cmd->add_option("--master-seed", a->master_seed, "[sweep] master_seed")->check(seedValidator())->group(o);
  cmd->add_option("--methods", a->methods, "[sweep] methods: ls, rls, pso, rls-pso, lad, ls-exact, ls-stacked, ls-parallel, idim-iv, ls-base, idim-iv-base, default (exoid identify's defaults); a chain's: ls, rls, pso, rls-pso, lad, iv-band, idim-iv")->delimiter(',')->group(o);
  cmd->add_option("--noise-tau", a->noise_tau, "[grid] torque_noise_Nm levels, e.g. 0,0.5")->delimiter(',')->group(o);
  cmd->add_option("--noise-q-deg", a->noise_q, "[grid] angle_noise_deg levels")->delimiter(',')->group(o);
  cmd->add_option("--quantisation-deg", a->quantisation, "[grid] quantisation_deg levels")->delimiter(',')->group(o);
  cmd->add_option("--vibration", a->vibration, "[grid] vibration_level levels")->delimiter(',')->group(o);
  cmd->add_option("--cylinder-mass-scale", a->cylinder, "[grid] cylinder_mass_scale levels")->delimiter(',')->group(o);
  cmd->add_option("--encoder-backlash-deg", a->backlash,
                  "[grid] encoder_backlash_deg levels: play between each joint and its encoder, deg (as simulate --encoder-backlash-deg; any leg)")
      ->delimiter(',')->group(o);
  cmd->add_option("--trajectories", a->trajectories, "[grid] trajectories levels: paper, optimised (the config's designs); a chain's: optimised, default")
      ->delimiter(',')->group(o);
  cmd->add_option("--duration", a->duration_s, "[simulation] duration_s of each record")->check(positiveNumber())->group(o);
  cmd->add_option("--pso-iterations", a->pso_iterations, "[identification] pso_iterations (G)")->check(positiveNumber())->group(o);
  cmd->add_option("--base-terms", a->base_terms, "[identification] base_terms: the 'default' arm's (a chain's every method's) "
                                                 "base-motion terms, as identify --base-terms: auto, on, off or judged")
      ->transform(CLI::CheckedTransformer(baseTermsChoices(), CLI::ignore_case))->group(o);
  cmd->callback([a] { runSweepCommand(*a); });
}

void addMergeCommand(CLI::App& app) {
  auto a = std::make_shared<MergeArgs>();
  CLI::App* cmd = app.add_subcommand("merge",
                                     "Combine the folders of `exoid sweep --shard K/N` runs into one, identical to a\n"
                                     "single-process sweep (runs.csv, summary.*).");
  cmd->add_option("--out", a->out, "Merged results folder")->required();
  cmd->add_option("shards", a->shards, "Shard folders")->required()->check(CLI::ExistingDirectory);
  cmd->add_flag("!--no-plots", a->plots, "Skip the figures");
  cmd->add_flag("--keep-edits", a->keep_edits, "Refuse, naming them, to rewrite outputs of --out changed by hand since exoid wrote them");
  cmd->callback([a] { mergeSweeps(a->shards, a->out, a->plots, std::cout, a->keep_edits); });
}

}  // namespace exoid::experiments
