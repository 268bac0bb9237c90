// `exoid excite`: design an excitation trajectory for the leg (ident::designExcitation) under the
// rig's limits, write it as JSON for `exoid simulate --excitation`, and compare it with the
// paper's trajectory on the same footing (condition number, Cramer-Rao bound per parameter).
#include "exoid/core/format.hpp"
#include "exoid/experiments/commands/robot_commands.hpp"
#include "exoid/experiments/commands/commands.hpp"
#include "exoid/experiments/protocol/excitation_io.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/experiments/report/plots.hpp"
#include "exoid/experiments/protocol/sim_bridge.hpp"
#include "exoid/experiments/report/table.hpp"
#include "exoid/core/atomic_file.hpp"
#include "exoid/sim/data_dir.hpp"
#include "exoid/sim/trajectory_json.hpp"
#include "exoid/sim/truth.hpp"

#include <filesystem>
#include <iostream>
#include <memory>

namespace exoid::experiments {

namespace {

struct ExciteArgs {
  std::string out;
  std::string model = sim::defaultModelPath();
  ident::ExcitationOptions options;
  double duration_s = 10.0, rate_hz = 1000.0, sigma_Nm = 0.5;  // the CRB comparison's footing
  bool knee_only = false;          ///< the hip locked (the segmental strategy's first stage)
  double hip_locked_at_deg = -10.0;
  // Overrides of the envelope's limits, "hip,knee" (empty = the paper's envelope).
  LimitOverrides overrides;
  std::string limits = "paper";  ///< "paper" (the envelope of its trajectories) or "urdf"
  std::string urdf = sim::dataPath("models/apal_leg.urdf");
  bool plot = true;  ///< <out>.png and <out>_series.csv next to the design
  CLI::App* cmd = nullptr;
  std::vector<std::string> armature;  ///< chain models: joints given an armature parameter the file lacks
  core::ChainSelection selection;     ///< chain models: --base, --tip, --lock
};

// The design and the paper's trajectory sampled over one period of the design: angle, speed,
// acceleration and nominal torque per joint (what the figure plots).
void writeSeriesCsv(const std::string& path, const core::FourierSeries& design, const core::FourierSeries& paper,
                    const ident::LegConstants& c, const ident::ParamVector& nominal) {
  core::writeFileAtomically(path, [&](std::ostream& o) {
    o << "t_s";
    for (const char* who : {"design", "paper"}) {
      for (const char* q : {"q", "qd", "qdd", "tau"}) o << ',' << who << '_' << q << "_hip," << who << '_' << q << "_knee";
    }
    o << '\n';
    const int n = 1000;
    for (int i = 0; i <= n; ++i) {
      const double t = design.period_s() * i / n;
      o << fmt(t, 8);
      for (const core::FourierSeries* tr : {&design, &paper}) {
        Eigen::Vector2d q, qd, qdd;
        tr->at(t, q, qd, qdd);
        ident::RegressorRow hip, knee;
        ident::regressorRows(c, q, qd, qdd, hip, knee);
        const Eigen::Vector2d tau(hip.dot(nominal), knee.dot(nominal));
        for (const Eigen::Vector2d& v : {q, qd, qdd, tau}) o << ',' << fmt(v[0], 10) << ',' << fmt(v[1], 10);
      }
      o << '\n';
    }
  });
}

// A chain model (not the APAL leg) is designed as a chain, with its own limits.
void exciteChainModel(const ExciteArgs& args) {
  for (const char* apal_only : {"--knee-only", "--hip-locked-at-deg", "--limits", "--urdf", "--duration", "--noise-tau"}) {
    if (args.cmd->count(apal_only) > 0) {
      throw CLI::ValidationError(apal_only, "is an option of the APAL leg's design; '" + args.model + "' is designed as a chain (its own limits)");
    }
  }
  ChainExciteArgs c;
  c.model = args.model;
  c.out = args.out;
  c.options = args.options;
  c.limits = args.overrides;
  c.armature = args.armature;
  c.selection = args.selection;
  exciteChain(c);
}

// The design's limits: the paper's envelope or the URDF's, then the command line's overrides.
ident::ExcitationLimits designLimits(const ExciteArgs& a, const ident::LegConstants& c, const ident::ParamVector& nominal) {
  ident::ExcitationLimits limits = paperEnvelope(c, nominal);
  if (a.limits == "urdf") {
    // The rig's own limits: joint range, speed and motor effort from the URDF; acceleration is
    // bounded through the effort by the nominal model, not separately.
    const sim::UrdfJointLimits u = sim::urdfJointLimits(a.urdf);
    for (int j = 0; j < 2; ++j) {
      const auto J = static_cast<std::size_t>(j);
      limits.q_min_rad[j] = u.lower_rad[J];
      limits.q_max_rad[j] = u.upper_rad[J];
      limits.qd_max_radps[j] = u.velocity_radps[J];
      limits.tau_max_Nm[j] = u.effort_Nm[J];
      limits.qdd_max_radps2[j] = 1e6;
    }
  }
  a.overrides.applyTo(limits);
  limits.validate({"hip", "knee"});
  return limits;
}

// The design against the paper's counterpart on the same footing: Cramer-Rao stds of both, and
// the floor no trajectory inside the limits can beat, over the parameters the design identifies.
struct ExciteComparison {
  int paper_id = 0;  ///< trajectory 1 for a knee-only design, 3 for both joints
  core::FourierSeries paper;
  ident::ExcitationScore paper_score;
  Eigen::VectorXd crb, crb_paper, floor;
  std::vector<int> indices;
};

ExciteComparison compareWithPaper(const ExciteArgs& a, const ident::ExcitationDesign& d, const ident::LegConstants& c,
                                  const ident::ParamVector& nominal, const ident::ExcitationLimits& limits) {
  ExciteComparison k;
  k.paper_id = a.knee_only ? 1 : 3;
  k.paper = sim::paperTrajectory(k.paper_id);
  k.paper_score = ident::scoreExcitation(ident::twoLinkLeg(c), k.paper, nominal, limits, 1000);
  k.crb = excitationCrb(d.trajectory, c, a.duration_s, a.rate_hz, a.sigma_Nm);
  k.crb_paper = excitationCrb(k.paper, c, a.duration_s, a.rate_hz, a.sigma_Nm);
  k.floor = ident::crbFloor(limits, c, a.knee_only, a.hip_locked_at_deg * M_PI / 180.0, a.duration_s * a.rate_hz, a.sigma_Nm);
  for (int i = a.knee_only ? ident::kShankFirst : 0; i < ident::kNumParams; ++i) k.indices.push_back(i);
  return k;
}

std::string limitsSource(const ExciteArgs& a) {
  const std::string source = a.limits == "urdf" ? "the URDF's joint limits (" + a.urdf + "), acceleration bounded by the effort"
                                                : "envelope of the paper's trajectories 1-4 on the nominal model";
  return a.overrides.empty() ? source : source + ", with overrides";
}

// The design file (what `exoid simulate --excitation` reads), with its limits and comparison.
nlohmann::json designJson(const ExciteArgs& a, const ident::ExcitationDesign& d, const ident::ExcitationLimits& limits,
                          const ExciteComparison& k) {
  nlohmann::json j;
  j["tool"] = toolJson();
  j["command"] = "excite";
  j["seed"] = a.options.seed;
  j["model"] = a.model;
  j["options"] = {{"criterion", ident::toString(a.options.criterion)}, {"harmonics", a.options.harmonics}, {"f0_hz", a.options.f0_hz}, {"hip_locked", a.knee_only},
                  {"hip_locked_at_rad", a.hip_locked_at_deg * M_PI / 180.0}, {"restarts", a.options.restarts},
                  {"max_evaluations", a.options.max_evaluations}, {"samples", a.options.samples}};
  j["criterion"] =
      std::string(a.options.criterion == ident::ExcitationCriterion::kCrb
                      ? "sum of log Cramer-Rao standard deviations of the LS estimates (D-optimality plus a penalty on their "
                        "correlations), minimised"
                      : "log condition number of the column-scaled regressor, minimised") +
      " over one period (both equations, 10 columns; knee-only: the knee equation's 5 shank columns)";
  j["limits"] = limitsJson(limits, limitsSource(a));
  j["trajectory"] = sim::trajectoryJson(d.trajectory, {"hip", "knee"});
  j["score"] = scoreJson(d);
  j["comparison"] = {{"footing", {{"duration_s", a.duration_s}, {"rate_hz", a.rate_hz}, {"sigma_Nm", a.sigma_Nm},
                                  {"note", "LS on raw torques, white noise on each joint"}}},
                     {"paper_trajectory", k.paper_id},
                     {"paper_condition_number", k.paper_score.condition_number},
                     {"crb_std", paramsJson(k.crb, k.indices)},
                     {"paper_crb_std", paramsJson(k.crb_paper, k.indices)},
                     {"crb_floor_std", paramsJson(k.floor, k.indices)},
                     {"crb_floor_note", "no trajectory inside the limits can do better (single-parameter Cauchy-Schwarz "
                                        "bound from the joint ranges, |qd| and |qdd| limits)"}};
  return j;
}

void printDesign(const ExciteArgs& a, const ident::ExcitationDesign& d, const ident::ExcitationLimits& limits, const ExciteComparison& k,
                 const std::string& figure) {
  std::cout << "excitation design (" << (a.knee_only ? "knee only, hip locked" : "both joints") << ", N = "
            << a.options.harmonics << ", f0 = " << fmt(a.options.f0_hz) << " Hz, seed " << a.options.seed << "): "
            << d.evaluations << " evaluations, " << d.feasible_restarts << "/" << a.options.restarts
            << " restarts feasible, " << fmt(d.wall_time_s, 3) << " s\n"
            << "criterion " << ident::toString(a.options.criterion) << "; condition number " << fmt(d.score.condition_number, 4)
            << " (paper's trajectory " << k.paper_id << ": " << fmt(k.paper_score.condition_number, 4) << ")\n";
  TextTable t({"param", "CRB std, design", "CRB std, paper's " + core::toText(k.paper_id), "gain", "floor", "max gain"});
  for (std::size_t i = 0; i < k.indices.size(); ++i) {
    const auto K = static_cast<Eigen::Index>(i);
    t.addRow({std::string(ident::paramName(k.indices[i])), fmt(k.crb[K], 3), fmt(k.crb_paper[K], 3), fmt(k.crb_paper[K] / k.crb[K], 3),
              fmt(k.floor[K], 3), fmt(k.crb_paper[K] / k.floor[K], 3)});
  }
  t.print(std::cout);
  std::cout << "(" << fmt(a.duration_s) << " s at " << fmt(a.rate_hz) << " Hz, " << fmt(a.sigma_Nm)
            << " N m white torque noise; LS on raw torques. gain = paper's std / design's; floor = the least std any\n"
               "trajectory inside these limits can reach, max gain = paper's std / floor)\n"
            << (limits.qdd_max_radps2.maxCoeff() >= 1e5
                    ? "(no acceleration limit here: the floors of the inertial and coupled gravity columns are not informative)\n"
                    : "")
            << "wrote "
            << a.out << (figure.empty() ? "" : " and " + figure) << "\n";
}

void runExcite(const ExciteArgs& args) {
  if (!sim::isApalLegModel(args.model) || !args.selection.empty()) return exciteChainModel(args);
  ExciteArgs a = args;
  if (a.knee_only) {
    a.options.locked_joints = 1;
    a.options.locked_at_rad = Eigen::VectorXd::Constant(1, a.hip_locked_at_deg * M_PI / 180.0);
  }
  a.options.validate();
  // The output checked before the design's seconds of work: its folder made, a file writable in it.
  core::prepareOutputFile(a.out);
  const sim::Truth truth = sim::truthFromModel(a.model);
  const ident::ParamVector nominal = toParamVector(truth.x);
  const ident::LegConstants c = constantsOf(truth);
  const ident::ExcitationLimits limits = designLimits(a, c, nominal);
  const ident::ExcitationDesign d = ident::designExcitation(a.options, ident::twoLinkLeg(c), nominal, limits);
  const ExciteComparison k = compareWithPaper(a, d, c, nominal, limits);
  writeJsonFile(a.out, designJson(a, d, limits, k));
  std::string figure;
  if (a.plot) {
    const std::string stem = a.out.size() > 5 && a.out.substr(a.out.size() - 5) == ".json" ? a.out.substr(0, a.out.size() - 5) : a.out;
    writeSeriesCsv(stem + "_series.csv", d.trajectory, k.paper, c, nominal);
    figure = stem + ".png";
    runPlotScript("excitation_plot.py", {stem + "_series.csv", a.out, figure});
  }
  printDesign(a, d, limits, k, figure);
}

}  // namespace

void addExciteCommand(CLI::App& app) {
  auto a = std::make_shared<ExciteArgs>();
  CLI::App* cmd = app.add_subcommand(
      "excite",
      "Design a periodic excitation trajectory (finite Fourier series, at rest at the period's ends) that\n"
      "minimises the parameters' Cramer-Rao bounds (--criterion crb, default) or the column-scaled condition\n"
      "number (cond), within the envelope of the paper's trajectories (joint ranges, |qd|, |qdd|, nominal |tau|)\n"
      "or the URDF's limits, and compare it with the paper's trajectory and with the floor no trajectory inside\n"
      "the limits can beat. `exoid simulate --excitation FILE` runs it.");
  cmd->add_option("--out", a->out, "Design JSON to write")->required();
  cmd->add_option("--model", a->model,
                  "The robot: apal (default), leg3 or an MJCF/URDF file: nominal parameters and, for a chain model, its\n"
                  "joints' limits (range; speed 3 rad/s, acceleration 30 rad/s^2 where the file gives none; motor torque)")
      ->transform([](const std::string& s) { return sim::modelPathFor(s); })
      ->check(CLI::ExistingFile)
      ->capture_default_str();
  cmd->add_flag("--knee-only", a->knee_only, "Design the knee-only record (hip locked), the segmental strategy's first stage");
  cmd->add_option("--hip-locked-at-deg", a->hip_locked_at_deg, "Knee-only: where the hip is held, deg (the paper's -10)")
      ->capture_default_str();
  cmd->add_option_function<std::string>(
         "--criterion", [a](const std::string& v) { a->options.criterion = ident::parseExcitationCriterion(v); },
         "crb: sum of log Cramer-Rao stds (D-optimality + decorrelation; rewards amplitude); cond: log condition number of "
         "the column-scaled regressor (scale free)")
      ->check(CLI::IsMember({"crb", "cond"}))
      ->default_str("crb");
  cmd->add_option("--harmonics", a->options.harmonics, "Harmonics per joint, >= 2")->capture_default_str();
  cmd->add_option("--f0", a->options.f0_hz, "Base frequency, Hz (the period is 1/f0)")->check(positiveNumber())->capture_default_str();
  cmd->add_option("--restarts", a->options.restarts, "Random starts of the optimiser, >= 1")->capture_default_str();
  cmd->add_option("--max-evaluations", a->options.max_evaluations, "Criterion evaluations per restart, >= 100")->capture_default_str();
  cmd->add_option("--seed", a->options.seed, "Seed of the random starts")->check(seedValidator())->capture_default_str();
  cmd->add_option("--limits", a->limits,
                  "paper: the envelope of the paper's trajectories (asks no more of the rig than the paper did); urdf: the "
                  "rig's joint range, speed and effort from --urdf")
      ->check(CLI::IsMember({"paper", "urdf"}))->capture_default_str();
  cmd->add_option("--urdf", a->urdf, "URDF with the hip and knee <limit>s (--limits urdf)")->check(CLI::ExistingFile)->capture_default_str();
  cmd->add_option("--q-min-deg", a->overrides.q_min_deg, "Override the lower joint limits, hip,knee in deg")->delimiter(',');
  cmd->add_option("--q-max-deg", a->overrides.q_max_deg, "Override the upper joint limits, hip,knee in deg")->delimiter(',');
  cmd->add_option("--qd-max", a->overrides.qd_max, "Override the speed limits, hip,knee in rad/s")->delimiter(',');
  cmd->add_option("--qdd-max", a->overrides.qdd_max, "Override the acceleration limits, hip,knee in rad/s^2")->delimiter(',');
  cmd->add_option("--tau-max", a->overrides.tau_max, "Override the torque limits (nominal model), hip,knee in N m")->delimiter(',');
  cmd->add_flag("!--no-plot", a->plot, "Skip the figure (<out>.png, the design and the paper's trajectory against the limits) and its <out>_series.csv");
  cmd->add_option("--duration", a->duration_s, "Comparison: record duration, s")->check(positiveNumber())->capture_default_str();
  cmd->add_option("--noise-tau", a->sigma_Nm, "Comparison: torque noise std, N m")->check(positiveNumber())->capture_default_str();
  addChainSelectionOptions(*cmd, a->selection);
  cmd->add_option("--armature", a->armature,
                  "Chain models: joints (comma-separated, or all) given an armature parameter where the file has none (a URDF\n"
                  "never does): the design then separates it too, as identify --armature fits it")
      ->delimiter(',');
  a->cmd = cmd;
  cmd->callback([a] { runExcite(*a); });
}

}  // namespace exoid::experiments
