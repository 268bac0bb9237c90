// `exoid excite`: design an excitation trajectory for any leg (protocol/excitation_design.hpp)
// under its limits, write it as JSON for `exoid simulate --excitation`, with each parameter's
// Cramer-Rao std; the APAL leg's design compared with the paper's trajectory on the same footing.
#include "exoid/experiments/commands/commands.hpp"
#include "exoid/experiments/protocol/excitation_design.hpp"
#include "exoid/experiments/protocol/robot_loader.hpp"
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/sim/model.hpp"

#include <memory>
#include <optional>
#include <tuple>

namespace exoid::experiments {

namespace {

struct ExciteArgs {
  ExciteRequest request;
  bool knee_only = false;                ///< the APAL leg's --first-moving knee
  std::optional<double> hip_locked_at_deg;  ///< the APAL leg's --held-at-deg
};

void runExcite(ExciteArgs a) {
  ExciteRequest& r = a.request;
  const bool apal = isApalLeg(r.model, r.selection);
  for (const auto& [given, name, generic] : {std::tuple{a.knee_only, "--knee-only", "--first-moving knee"},
                                             std::tuple{a.hip_locked_at_deg.has_value(), "--hip-locked-at-deg", "--held-at-deg"}}) {
    if (given && !apal) {
      throw CLI::ValidationError(name, std::string("is the APAL leg's spelling of ") + generic + "; '" + r.model +
                                           "' is a chain: --first-moving JOINT holds the joints above JOINT (--held-at-deg)");
    }
  }
  if (a.knee_only) {
    if (!r.first_moving.empty() && r.first_moving != "knee") throw CLI::ValidationError("--knee-only", "contradicts --first-moving " + r.first_moving);
    r.first_moving = "knee";
  }
  if (a.hip_locked_at_deg) {
    if (!r.held_at_deg.empty()) throw CLI::ValidationError("--hip-locked-at-deg", "give it once (or --held-at-deg)");
    if (r.first_moving != "knee") throw CLI::ValidationError("--hip-locked-at-deg", "holds the hip of a knee-only design: give --knee-only too");
    r.held_at_deg = {*a.hip_locked_at_deg};
  }
  excite(r);
}

}  // namespace

void addExciteCommand(CLI::App& app) {
  auto a = std::make_shared<ExciteArgs>();
  ExciteRequest& r = a->request;
  CLI::App* cmd = app.add_subcommand(
      "excite",
      "Design a periodic excitation trajectory (finite Fourier series, at rest at the period's ends) for any\n"
      "leg that minimises its parameters' Cramer-Rao bounds (--criterion crb, default) or the column-scaled\n"
      "condition number (cond), every joint moving or the joints above --first-moving held (a stage's record).\n"
      "The APAL leg's limits are the envelope of the paper's trajectories (joint ranges, |qd|, |qdd|, nominal\n"
      "|tau|) or its URDF's, and its design is compared with the paper's trajectory and with the floor no\n"
      "trajectory inside the limits can beat; a chain's limits are its model file's. `exoid simulate\n"
      "--excitation FILE` runs it.");
  cmd->add_option("--out", r.out, "Design JSON to write")->required();
  cmd->add_option("--model", r.model,
                  "The robot: apal (default), leg3 or an MJCF/URDF file: nominal parameters and, for a chain model, its\n"
                  "joints' limits (range; speed 3 rad/s, acceleration 30 rad/s^2 where the file gives none; motor torque)")
      ->transform([](const std::string& s) { return sim::modelPathFor(s); })
      ->check(CLI::ExistingFile)
      ->capture_default_str();
  cmd->add_option("--first-moving", r.first_moving,
                  "Design a stage's record: the joints above this one held (exoid simulate holds them where the design\n"
                  "does; identify --stage JOINT=FILE fits it). Default: every joint moves");
  cmd->add_option("--held-at-deg", r.held_at_deg,
                  "Where each held joint is held, deg, comma-separated (default: the APAL leg's hip at the paper's -10; a\n"
                  "chain's joint at 0, or its range's middle when 0 is outside the range's middle 80 %)")
      ->delimiter(',');
  cmd->add_flag("--knee-only", a->knee_only, "The APAL leg: the knee-only record (hip locked), the segmental strategy's first stage (= --first-moving knee)");
  cmd->add_option_function<double>(
      "--hip-locked-at-deg", [a](double v) { a->hip_locked_at_deg = v; }, "The APAL leg's knee-only record: where the hip is held, deg (= --held-at-deg)");
  cmd->add_option_function<std::string>(
         "--criterion", [a](const std::string& v) { a->request.options.criterion = ident::parseExcitationCriterion(v); },
         "crb: sum of log Cramer-Rao stds (D-optimality + decorrelation; rewards amplitude); cond: log condition number of "
         "the column-scaled regressor (scale free)")
      ->check(CLI::IsMember({"crb", "cond"}))
      ->default_str("crb");
  cmd->add_option("--harmonics", r.options.harmonics, "Harmonics per joint, >= 2")->capture_default_str();
  cmd->add_option("--f0", r.options.f0_hz, "Base frequency, Hz (the period is 1/f0)")->check(positiveNumber())->capture_default_str();
  cmd->add_option("--restarts", r.options.restarts, "Random starts of the optimiser, >= 1")->capture_default_str();
  cmd->add_option("--max-evaluations", r.options.max_evaluations, "Criterion evaluations per restart, >= 100")->capture_default_str();
  cmd->add_option("--seed", r.options.seed, "Seed of the random starts")->check(seedValidator())->capture_default_str();
  cmd->add_option("--limits", r.limits,
                  "The APAL leg: paper, the envelope of the paper's trajectories (asks no more of the rig than the paper did);\n"
                  "urdf, the rig's joint range, speed and effort from --urdf. A chain's are its model file's")
      ->check(CLI::IsMember({"paper", "urdf"}))->capture_default_str();
  cmd->add_option("--urdf", r.urdf, "The APAL leg: the URDF with the hip and knee <limit>s (--limits urdf)")
      ->check(CLI::ExistingFile)->default_str("models/apal_leg.urdf");
  cmd->add_option("--q-min-deg", r.overrides.q_min_deg, "Override the lower joint limits, one per joint in deg")->delimiter(',');
  cmd->add_option("--q-max-deg", r.overrides.q_max_deg, "Override the upper joint limits, one per joint in deg")->delimiter(',');
  cmd->add_option("--qd-max", r.overrides.qd_max, "Override the speed limits, one per joint in rad/s")->delimiter(',');
  cmd->add_option("--qdd-max", r.overrides.qdd_max, "Override the acceleration limits, one per joint in rad/s^2")->delimiter(',');
  cmd->add_option("--tau-max", r.overrides.tau_max, "Override the torque limits (nominal model), one per joint in N m")->delimiter(',');
  cmd->add_flag("!--no-plot", r.plot,
                "Skip the figure (<out>.png: the design, and the APAL leg's paper trajectory, against the limits) and its\n"
                "<out>_series.csv");
  cmd->add_option("--duration", r.duration_s, "Cramer-Rao footing: record duration, s")->check(positiveNumber())->capture_default_str();
  cmd->add_option("--noise-tau", r.sigma_Nm, "Cramer-Rao footing: torque noise std, N m")->check(positiveNumber())->capture_default_str();
  addChainSelectionOptions(*cmd, r.selection);
  cmd->add_option("--armature", r.armature,
                  "Chain models: joints (comma-separated, or all) given an armature parameter where the file has none (a URDF\n"
                  "never does): the design then separates it too, as identify --armature fits it")
      ->delimiter(',');
  cmd->callback([a] { runExcite(*a); });
}

}  // namespace exoid::experiments
