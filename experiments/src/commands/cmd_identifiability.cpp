// `exoid identifiability`: what a record can identify, before anyone runs an experiment.
#include "exoid/core/atomic_file.hpp"
#include "exoid/experiments/commands/commands.hpp"
#include "exoid/experiments/report/cells.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/protocol/log_input.hpp"
#ifdef EXOID_WITH_MUJOCO
#include "exoid/experiments/protocol/model_report.hpp"
#endif
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/experiments/report/table.hpp"
#include "exoid/ident/signals/band.hpp"
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/design/identifiability.hpp"
#include "exoid/ident/design/identifiability_advice.hpp"
#include "exoid/ident/signals/processing.hpp"

#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <optional>

namespace exoid::experiments {

namespace {

struct Args {
  std::string data, json_out, reference, model;
  std::vector<std::string> armature;  ///< --model: joints given an armature parameter the file lacks
  core::ChainSelection selection;     ///< --model: --base, --tip, --lock
  double noise_tau_Nm = 0.5;
  ConstantsFlags constants;
  LogInputFlags log;
  ident::SignalOptions signals = defaultIdentifySignals();
};

struct Block {
  std::string name;
  std::vector<int> columns;
  std::vector<ident::NoiseChannel> channels;  // rows of H by torque channel (hip, knee)
  Eigen::VectorXd y;
};

// What the relative stds are relative to: --reference, else the truth exoid simulate stored beside
// the record, else nothing (a record's own estimate is no yardstick: when it is absurd, any std
// looks small against it).
struct Reference {
  ident::ParamVector x = ident::ParamVector::Constant(std::numeric_limits<double>::quiet_NaN());
  std::string origin;  // empty: none
};

Reference pickReference(const std::map<std::string, ident::ParamVector>& truths, const std::string& file) {
  // The rigid links before the best fit: a record's best fit is itself arbitrary in what the
  // record cannot identify (fc1 with the hip locked), the physical parameters are not.
  static const std::pair<const char*, const char*> kPreferred[] = {
      {"truth", "the parameters"}, {"rigid", "the rigid-link truth"}, {"best_fit", "the best-fit truth"}};
  for (const auto& [key, label] : kPreferred) {
    if (const auto it = truths.find(key); it != truths.end()) return {it->second, std::string(label) + " in " + file};
  }
  throw std::invalid_argument(file + ": no parameters found (expected {\"parameters\": {...}} or exoid's sidecar with "
                              "truth.rigid / truth.best_fit)");
}

Reference resolveReference(const Args& a) {
  if (!a.reference.empty()) return pickReference(readTruthFile(a.reference), a.reference);
  for (const std::string ext : {".csv.gz", ".csv"}) {
    if (a.data.size() <= ext.size() || !endsWith(a.data, ext)) continue;
    const std::string sidecar = a.data.substr(0, a.data.size() - ext.size()) + ".json";
    if (!std::filesystem::exists(sidecar)) break;
    // Only exoid's sidecar counts; any other JSON of that name is not a reference.
    std::map<std::string, ident::ParamVector> truths;
    try {
      truths = readTruthFile(sidecar);
    } catch (const std::invalid_argument&) {
      break;
    }
    if (truths.count("rigid") || truths.count("best_fit")) return pickReference(truths, sidecar);
    break;
  }
  return {};
}

Eigen::MatrixXd pick(const Eigen::MatrixXd& H, const std::vector<int>& cols) {
  Eigen::MatrixXd out(H.rows(), static_cast<Eigen::Index>(cols.size()));
  for (std::size_t k = 0; k < cols.size(); ++k) out.col(static_cast<Eigen::Index>(k)) = H.col(cols[k]);
  return out;
}

// --model: what the model lets any record identify.
void reportModelOnly(const Args& a) {
  if (!a.data.empty()) {
    throw std::invalid_argument("--model with --data: a record's identifiability is reported for the built-in APAL leg "
                                "only so far; give --model alone for what the model lets anyone identify");
  }
#ifdef EXOID_WITH_MUJOCO
  reportModel(a.model, a.json_out, std::cout, a.armature, a.selection);
#else
  throw std::invalid_argument("--model: this exoid was built without MuJoCo and urdfdom, which read robot models");
#endif
}

// The record, processed as identify would: in the band chosen from it unless the flags fix it.
struct ProcessedInput {
  ident::Dataset d;
  ident::LegConstants c;
  ident::SignalOptions signals;
  std::optional<ident::BandChoice> band;
  ident::RecordRows s;
};

ProcessedInput processInput(const Args& a) {
  const LogInput log = resolveLogInput(a.log, a.signals.filter ? a.signals.cutoff_hz : 0.0);
  ProcessedInput in;
  in.d = readLog(a.data, log);
  in.c = resolveConstants(a.constants, in.d, nullptr, log.thigh_length_m, log.gravity_mps2);
  in.signals = a.signals;
  try {
    const ident::Robot robot = ident::twoLinkLeg(in.c);
    in.signals = ident::resolveSignalOptions(in.d, robot, in.signals, {}, &in.band);
    if (in.band) std::cout << "band: " << in.band->describe() << " (--cutoff-hz, --derivative-cutoff-hz, --decimation override)\n";
    in.s = ident::processRecord(in.d, robot, in.signals);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(a.data + ": " + e.what() + timeUnitHint(in.d));
  }
  return in;
}

// Both equations with all 10 parameters, the hip's with the thigh's 5, the knee's with the shank's 5.
std::vector<Block> blocksOf(const ProcessedInput& in, double noise_tau_Nm) {
  const std::vector<int> all{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}, thigh{0, 1, 2, 3, 4}, shank{5, 6, 7, 8, 9};
  const ident::RecordRows& s = in.s;
  const Eigen::MatrixXd Hh = s.jointW(0);
  const Eigen::MatrixXd Hk = s.jointW(1);
  const Eigen::VectorXd tau_hip = s.jointY(0), tau_knee = s.jointY(1);
  // White torque noise of std noise_tau reaches the fit through this record's processing.
  const ident::TorqueNoisePath path = ident::torqueNoisePath(in.signals, 1.0 / in.d.sampleInterval_s(), in.d.size());
  const double sg = noise_tau_Nm;
  Eigen::VectorXd y_all(2 * s.samples());
  y_all << tau_hip, tau_knee;
  return {
      {"both equations, all 10", all, {{Hh, path, sg}, {Hk, path, sg}}, y_all},
      {"hip equation, params 1-5", thigh, {{pick(Hh, thigh), path, sg}}, tau_hip},
      {"knee equation, params 6-10", shank, {{pick(Hk, shank), path, sg}}, tau_knee},
  };
}

nlohmann::json reportJson(const Args& a, const ProcessedInput& in, const Reference& ref) {
  nlohmann::json j;
  j["tool"] = toolJson();
  j["command"] = "identifiability";
  j["data"] = a.data;
  j["noise_tau_Nm"] = a.noise_tau_Nm;
  j["constants"] = {{"thigh_length_m", in.c.thigh_length_m}, {"gravity_mps2", in.c.gravity_mps2}};
  j["signal_options"] = toJson(in.signals);
  if (in.band) {
    j["band"] = {{"motion_bandwidth_hz", in.band->motion_bandwidth_hz}, {"limited_by", in.band->limited_by}, {"reason", in.band->describe()}};
  }
  j["reference"] = ref.origin.empty() ? nlohmann::json(nullptr) : nlohmann::json{{"origin", ref.origin}, {"parameters", paramsJson(ref.x)}};
  return j;
}

// The block's rows of every channel, stacked (its columns already).
Eigen::MatrixXd stackedRows(const Block& b) {
  Eigen::Index rows = 0;
  for (const ident::NoiseChannel& ch : b.channels) rows += ch.H.rows();
  Eigen::MatrixXd H(rows, static_cast<Eigen::Index>(b.columns.size()));
  rows = 0;
  for (const ident::NoiseChannel& ch : b.channels) {
    H.middleRows(rows, ch.H.rows()) = ch.H;
    rows += ch.H.rows();
  }
  return H;
}

// Per parameter of the block: CRB std (absolute, relative) and collinearity, printed and into bj.
void reportParameters(const Block& b, const ident::IdentifiabilityReport& r, nlohmann::json& bj) {
  TextTable t({"param", "CRB std", "CRB rel std", "R^2 on others"});
  for (std::size_t k = 0; k < b.columns.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    const std::string n(ident::paramName(b.columns[k]));
    const bool finite = std::isfinite(r.crb_rel_std[i]);
    t.addRow({n, std::isfinite(r.crb_std[i]) ? fmt(r.crb_std[i], 3) : "inf",
              std::isnan(r.crb_rel_std[i]) ? "-" : finite ? fixed(100.0 * r.crb_rel_std[i], 2) + " %" : "inf",
              fixed(r.collinearity_r2[i], 5)});
    bj["crb_std"][n] = jsonNumber(r.crb_std[i]);
    bj["crb_rel_std"][n] = finite ? nlohmann::json(r.crb_rel_std[i]) : nlohmann::json(nullptr);
    bj["collinearity_r2"][n] = r.collinearity_r2[i];
  }
  t.print(std::cout);
}

// One block: rank, condition, what it cannot identify, each parameter's bound, and the same in
// words (what is missing and what motion would supply it); printed and returned as JSON.
nlohmann::json reportBlock(const Block& b, const Reference& ref) {
  const ident::IdentifiabilityReport r = ident::analyzeIdentifiability(b.channels, b.y, ref.x(b.columns));
  std::cout << '\n' << b.name << ": rank " << r.rank << " of " << b.columns.size() << ", condition (scaled) "
            << (std::isfinite(r.condition_number) ? fmt(r.condition_number, 4) : std::string("inf"));
  nlohmann::json bj = {{"block", b.name}, {"rank", r.rank}, {"columns", b.columns.size()}};
  bj["condition_number"] = jsonNumber(r.condition_number);
  nlohmann::json unid = nlohmann::json::array();
  std::string names;
  for (Eigen::Index k : r.unidentifiable) {
    const std::string n(ident::paramName(b.columns[static_cast<std::size_t>(k)]));
    unid.push_back(n);
    names += (names.empty() ? "" : ", ") + n;
  }
  bj["unidentifiable"] = unid;
  if (!names.empty()) std::cout << "; NOT identifiable: " << names;
  std::cout << '\n';
  reportParameters(b, r, bj);
  bj["advice"] = ident::identifiabilityAdvice(stackedRows(b), r, b.columns);
  for (const std::string& line : bj["advice"].get<std::vector<std::string>>()) std::cout << "- " << line << '\n';
  return bj;
}

void run(const Args& a) {
  if (!a.model.empty()) return reportModelOnly(a);
  if (!a.selection.empty()) throw std::invalid_argument("--base/--tip/--lock pick a chain out of --model FILE: give --model");
  if (a.data.empty()) throw std::invalid_argument("give --data (a record: what it identifies) or --model (a robot model: what any record can)");
  if (!a.json_out.empty()) core::checkOutputWritable(a.json_out);  // before the work, not after it
  const ProcessedInput in = processInput(a);
  const std::vector<Block> blocks = blocksOf(in, a.noise_tau_Nm);
  const Reference ref = resolveReference(a);
  nlohmann::json j = reportJson(a, in, ref);
  std::cout << "Record " << a.data << ": " << in.s.samples() << " samples; torque noise " << a.noise_tau_Nm
            << " N m through this processing (Cramer-Rao std of the filtered, trimmed fit).\n"
            << (ref.origin.empty() ? "Relative stds: not shown, no reference (--reference FILE: the truth or your leg's "
                                     "nominal parameters); the advice judges by collinearity."
                                   : "Relative stds: relative to " + ref.origin + ".")
            << '\n';
  for (const Block& b : blocks) j["blocks"].push_back(reportBlock(b, ref));
  if (!a.json_out.empty()) writeJsonFile(a.json_out, j);
}

}  // namespace

void addIdentifiabilityCommand(CLI::App& app) {
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "identifiability",
      "Say what a record can identify: rank and condition number (columns scaled) of the stacked\n"
      "and of each joint's regressor, unidentifiable parameters, Cramer-Rao std at a torque noise\n"
      "level (relative to --reference or the record's simulated truth when known), and each\n"
      "column's collinearity (R^2 on the others).");
  cmd->add_option("--data", args->data, "Dataset CSV (the APAL leg's columns)")->check(CLI::ExistingFile);
  cmd->add_option("--model", args->model,
                  "A robot model instead of a record: 'apal', 'leg3' (built in) or an MJCF / URDF file. Prints its\n"
                  "serial chain and base parameters: rank, each identifiable combination of the standard parameters\n"
                  "in words with its true value, what no torque shows, what is regrouped");
#ifdef EXOID_WITH_MUJOCO
  addChainSelectionOptions(*cmd, args->selection);
  cmd->add_option("--armature", args->armature,
                  "--model: joints (comma-separated, or all) given an armature parameter (a geared motor's reflected rotor\n"
                  "inertia) where the file has none, as identify --armature")
      ->delimiter(',');
#endif
  cmd->add_option("--noise-tau", args->noise_tau_Nm, "Torque noise std for the Cramer-Rao bound, N m")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  cmd->add_option("--json", args->json_out, "Write the report as JSON here");
  cmd->add_option("--reference", args->reference,
                  "Parameters the relative stds are relative to: JSON {\"parameters\": {\"Mxt\": ..}} (your leg's\n"
                  "nominal values) or an exoid sidecar / truth file. Default: the sidecar exoid simulate wrote\n"
                  "beside the record (its rigid-link truth), else none (absolute stds only)")
      ->check(CLI::ExistingFile);
  addConstantsOptions(*cmd, args->constants);
  addLogInputOptions(*cmd, args->log);
  addSignalOptions(*cmd, args->signals);
  cmd->callback([args] { run(*args); });
}

}  // namespace exoid::experiments
