// `exoid identifiability`: what a record can identify, before anyone runs an experiment.
#include "exoid/core/atomic_file.hpp"
#include "exoid/core/format.hpp"
#include "exoid/experiments/commands/commands.hpp"
#include "exoid/experiments/report/cells.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/protocol/log_input.hpp"
#ifdef EXOID_WITH_MUJOCO
#include "exoid/experiments/protocol/model_report.hpp"
#include "exoid/experiments/protocol/robot_loader.hpp"
#endif
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/experiments/report/table.hpp"
#include "exoid/ident/signals/band.hpp"
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/design/identifiability.hpp"
#include "exoid/ident/design/identifiability_advice.hpp"
#include "exoid/ident/signals/processing.hpp"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace exoid::experiments {

namespace {

struct Args {
  std::string data, json_out, reference, model;
  std::vector<std::string> armature;  ///< --model: joints given an armature parameter the file lacks
  bool knee_armature = false;         ///< the APAL leg: Ia2 among the parameters (identify --knee-armature)
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
// the record, else (a chain model) the model file's own parameters, else nothing (a record's own
// estimate is no yardstick: when it is absurd, any std looks small against it).
struct Reference {
  Eigen::VectorXd x;  ///< NaN: none
  std::string origin;  // empty: none
};

Reference pickReference(const std::map<std::string, ident::ParamVector>& truths, const std::string& file) {
  // The rigid links before the best fit: a record's best fit is itself arbitrary in what the
  // record cannot identify (fc1 with the hip locked), the physical parameters are not.
  static const std::pair<const char*, const char*> kPreferred[] = {
      {"truth", "the parameters"}, {"rigid", "the rigid-link truth"}, {"best_fit", "the best-fit truth"}};
  for (const auto& [key, label] : kPreferred) {
    if (const auto it = truths.find(key); it != truths.end()) return {Eigen::VectorXd(it->second), std::string(label) + " in " + file};
  }
  throw std::invalid_argument(file + ": no parameters found (expected {\"parameters\": {...}} or exoid's sidecar with "
                              "truth.rigid / truth.best_fit)");
}

Eigen::MatrixXd pick(const Eigen::MatrixXd& H, const std::vector<int>& cols) {
  Eigen::MatrixXd out(H.rows(), static_cast<Eigen::Index>(cols.size()));
  for (std::size_t k = 0; k < cols.size(); ++k) out.col(static_cast<Eigen::Index>(k)) = H.col(cols[k]);
  return out;
}

// A chain model other than the APAL leg (the APAL leg is the 2-link leg of the record's constants).
bool chainModel(const Args& a) {
#ifdef EXOID_WITH_MUJOCO
  return !a.model.empty() && !isApalLeg(a.model, a.selection);
#else
  return !a.model.empty();
#endif
}

// The record, processed as identify would (in the band chosen from it unless the flags fix it),
// with the robot it is read as and the reference its relative stds are relative to.
struct ProcessedInput {
  ident::Dataset d;
  ident::Robot robot;
  std::optional<ident::LegConstants> c;  ///< the APAL leg's constants
  ident::SignalOptions signals;
  std::optional<ident::BandChoice> band;
  ident::RecordRows s;
  Reference reference;
};

// The JSON beside a record (x.csv or x.csv.gz: x.json) when there is one, else "".
std::string sidecarBeside(const std::string& data) {
  for (const std::string ext : {".csv.gz", ".csv"}) {
    if (data.size() <= ext.size() || !endsWith(data, ext)) continue;
    const std::string sidecar = data.substr(0, data.size() - ext.size()) + ".json";
    return std::filesystem::exists(sidecar) ? sidecar : "";
  }
  return "";
}

// The APAL leg's reference: --reference, else the truth exoid simulate stored beside the record.
Reference legReference(const Args& a) {
  if (!a.reference.empty()) return pickReference(readTruthFile(a.reference), a.reference);
  const std::string sidecar = sidecarBeside(a.data);
  if (sidecar.empty()) return {};
  // Only exoid's sidecar counts; any other JSON of that name is not a reference.
  std::map<std::string, ident::ParamVector> truths;
  try {
    truths = readTruthFile(sidecar);
  } catch (const std::invalid_argument&) {
    return {};
  }
  if (truths.count("rigid") || truths.count("best_fit")) return pickReference(truths, sidecar);
  return {};
}

ProcessedInput processInput(const Args& a) {
  ProcessedInput in;
  std::vector<std::string> joints = {"hip", "knee"};
#ifdef EXOID_WITH_MUJOCO
  std::optional<LoadedChain> loaded;
  if (chainModel(a)) {
    loaded = loadChain(a.model, a.armature, a.selection);
    joints = loaded->model.jointNames();
    in.robot = loaded->robot;
  }
#else
  if (chainModel(a)) throw std::invalid_argument("--model: this exoid was built without MuJoCo and urdfdom, which read robot models");
#endif
  LogInput log = resolveLogInput(a.log, a.signals.filter ? a.signals.cutoff_hz : 0.0, joints);
#ifdef EXOID_WITH_MUJOCO
  if (loaded) log.check_record = recordOfChain(*loaded);
#endif
  in.d = readLog(a.data, log);
  if (!chainModel(a)) {
    in.c = resolveConstants(a.constants, in.d, nullptr, log.thigh_length_m, log.gravity_mps2);
    in.robot = ident::twoLinkLeg(*in.c, a.knee_armature);
    in.reference = legReference(a);
    // A reference of X gives none for the armature.
    if (a.knee_armature && in.reference.x.size() == ident::kNumParams) {
      in.reference.x.conservativeResize(in.robot.parameters());
      in.reference.x[ident::kKneeArmature] = std::numeric_limits<double>::quiet_NaN();
    }
  }
#ifdef EXOID_WITH_MUJOCO
  if (loaded) {
    // --reference, else the sidecar of a chain simulation beside the record, else the model file's own parameters.
    const std::string sidecar = a.reference.empty() ? sidecarBeside(a.data) : a.reference;
    try {
      if (!sidecar.empty()) in.reference = {truthFromSidecar(sidecar, *loaded), "the parameters in " + sidecar};
    } catch (const std::invalid_argument& e) {
      if (!a.reference.empty()) throw std::invalid_argument(std::string("--reference: ") + e.what());
      std::cout << "reference: not the sidecar beside the record (" << e.what() << ")\n";
    }
    if (in.reference.origin.empty()) in.reference = {loaded->base.combination * loaded->phi, "the model file's own parameters (" + loaded->path + ")"};
  }
#endif
  in.signals = a.signals;
  try {
    in.signals = ident::resolveSignalOptions(in.d, in.robot, in.signals, {}, &in.band);
    if (in.band) std::cout << "band: " << in.band->describe() << " (--cutoff-hz, --derivative-cutoff-hz, --decimation override)\n";
    in.s = ident::processRecord(in.d, in.robot, in.signals);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(a.data + ": " + e.what() + timeUnitHint(in.d));
  }
  if (in.reference.x.size() == 0) in.reference.x = Eigen::VectorXd::Constant(in.robot.parameters(), std::numeric_limits<double>::quiet_NaN());
  return in;
}

// "params 1-5" (1-based, contiguous), else the names.
std::string paramsText(const ident::Robot& robot, const std::vector<int>& columns) {
  bool contiguous = true;
  for (std::size_t k = 1; k < columns.size(); ++k) contiguous = contiguous && columns[k] == columns[k - 1] + 1;
  if (contiguous) return "params " + core::toText(columns.front() + 1) + "-" + core::toText(columns.back() + 1);
  std::string s;
  for (int c : columns) s += (s.empty() ? "" : ", ") + robot.names()[static_cast<std::size_t>(c)];
  return s;
}

// Every equation with every parameter; then each joint's equation with the parameters no joint
// below it has (what it determines once the distal ones are known: the APAL leg's hip with the
// thigh's 5, its knee with the shank's 5).
std::vector<Block> blocksOf(const ProcessedInput& in, double noise_tau_Nm) {
  const ident::Robot& robot = in.robot;
  const ident::RecordRows& s = in.s;
  const int dof = robot.dof(), p = robot.parameters();
  // White torque noise of std noise_tau reaches the fit through this record's processing.
  const ident::TorqueNoisePath path = ident::torqueNoisePath(in.signals, 1.0 / in.d.sampleInterval_s(), in.d.size());
  const double sg = noise_tau_Nm;
  Block all{std::string(dof == 2 ? "both equations" : "all " + core::toText(dof) + " equations") + ", all " + core::toText(p), {}, {},
            Eigen::VectorXd(dof * s.samples())};
  for (int i = 0; i < p; ++i) all.columns.push_back(i);
  std::vector<Block> out;
  for (int j = 0; j < dof; ++j) {
    all.channels.push_back({s.jointW(j), path, sg});
    all.y.segment(j * s.samples(), s.samples()) = s.jointY(j);
  }
  out.push_back(all);
  for (int j = 0; j < dof; ++j) {
    std::vector<int> own;
    for (int c : robot.joint_columns[static_cast<std::size_t>(j)]) {
      bool below = false;
      for (int k = j + 1; k < dof; ++k) {
        const std::vector<int>& b = robot.joint_columns[static_cast<std::size_t>(k)];
        below = below || std::find(b.begin(), b.end(), c) != b.end();
      }
      if (!below) own.push_back(c);
    }
    if (own.empty()) continue;
    out.push_back({robot.jointNames()[static_cast<std::size_t>(j)] + " equation, " + paramsText(robot, own), own,
                   {{pick(s.jointW(j), own), path, sg}}, s.jointY(j)});
  }
  return out;
}

nlohmann::json reportJson(const Args& a, const ProcessedInput& in) {
  const Reference& ref = in.reference;
  nlohmann::json j;
  j["tool"] = toolJson();
  j["command"] = "identifiability";
  j["data"] = a.data;
  j["noise_tau_Nm"] = a.noise_tau_Nm;
  if (in.c) j["constants"] = {{"thigh_length_m", in.c->thigh_length_m}, {"gravity_mps2", in.c->gravity_mps2}};
  if (!a.model.empty()) j["model"] = a.model;
  j["signal_options"] = toJson(in.signals);
  if (in.band) {
    j["band"] = {{"motion_bandwidth_hz", in.band->motion_bandwidth_hz}, {"limited_by", in.band->limited_by}, {"reason", in.band->describe()}};
  }
  nlohmann::json values = nlohmann::json::object();
  for (Eigen::Index i = 0; i < ref.x.size(); ++i) values[in.robot.names()[static_cast<std::size_t>(i)]] = jsonNumber(ref.x[i]);
  j["reference"] = ref.origin.empty() ? nlohmann::json(nullptr) : nlohmann::json{{"origin", ref.origin}, {"parameters", values}};
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
void reportParameters(const ident::Robot& robot, const Block& b, const ident::IdentifiabilityReport& r, nlohmann::json& bj) {
  TextTable t({"param", "CRB std", "CRB rel std", "R^2 on others"});
  for (std::size_t k = 0; k < b.columns.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    const std::string& n = robot.names()[static_cast<std::size_t>(b.columns[k])];
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
nlohmann::json reportBlock(const ident::Robot& robot, const Block& b, const Reference& ref) {
  const ident::IdentifiabilityReport r = ident::analyzeIdentifiability(b.channels, b.y, ref.x(b.columns));
  std::cout << '\n' << b.name << ": rank " << r.rank << " of " << b.columns.size() << ", condition (scaled) "
            << (std::isfinite(r.condition_number) ? fmt(r.condition_number, 4) : std::string("inf"));
  nlohmann::json bj = {{"block", b.name}, {"rank", r.rank}, {"columns", b.columns.size()}};
  bj["condition_number"] = jsonNumber(r.condition_number);
  nlohmann::json unid = nlohmann::json::array();
  std::string names;
  for (Eigen::Index k : r.unidentifiable) {
    const std::string& n = robot.names()[static_cast<std::size_t>(b.columns[static_cast<std::size_t>(k)])];
    unid.push_back(n);
    names += (names.empty() ? "" : ", ") + n;
  }
  bj["unidentifiable"] = unid;
  if (!names.empty()) std::cout << "; NOT identifiable: " << names;
  std::cout << '\n';
  reportParameters(robot, b, r, bj);
  bj["advice"] = ident::identifiabilityAdvice(stackedRows(b), r, robot, b.columns);
  for (const std::string& line : bj["advice"].get<std::vector<std::string>>()) std::cout << "- " << line << '\n';
  return bj;
}

void run(const Args& given) {
  Args a = given;
  if (!a.model.empty() && a.data.empty()) {
#ifdef EXOID_WITH_MUJOCO
    return reportModel(a.model, a.json_out, std::cout, a.armature, a.selection);  // what the model lets any record identify
#else
    throw std::invalid_argument("--model: this exoid was built without MuJoCo and urdfdom, which read robot models");
#endif
  }
  if (!a.selection.empty() && a.model.empty()) throw std::invalid_argument("--base/--tip/--lock pick a chain out of --model FILE: give --model");
  if (chainModel(a) && (a.constants.thigh_length_m || a.constants.gravity_mps2)) {
    throw CLI::ValidationError(a.constants.thigh_length_m ? "--thigh-length" : "--gravity",
                               "is the APAL leg's; a chain model (--model " + a.model + ") takes its lengths and gravity from its file");
  }
  if (!chainModel(a)) {  // the APAL leg: --armature knee is its --knee-armature (options.hpp)
    a.knee_armature = apalKneeArmature(a.armature) || a.knee_armature;
    a.armature.clear();
  }
  if (a.knee_armature && chainModel(a)) {
    throw CLI::ValidationError("--knee-armature", "is the APAL leg's; a chain model's armatures are --armature JOINT,...");
  }
  if (a.data.empty()) throw std::invalid_argument("give --data (a record: what it identifies) or --model (a robot model: what any record can)");
  if (!a.json_out.empty()) core::checkOutputWritable(a.json_out);  // before the work, not after it
  const ProcessedInput in = processInput(a);
  const std::vector<Block> blocks = blocksOf(in, a.noise_tau_Nm);
  const Reference& ref = in.reference;
  nlohmann::json j = reportJson(a, in);
  std::cout << "Record " << a.data << ": " << in.s.samples() << " samples; torque noise " << a.noise_tau_Nm
            << " N m through this processing (Cramer-Rao std of the filtered, trimmed fit).\n"
            << (ref.origin.empty() ? "Relative stds: not shown, no reference (--reference FILE: the truth or your leg's "
                                     "nominal parameters); the advice judges by collinearity."
                                   : "Relative stds: relative to " + ref.origin + ".")
            << '\n';
  for (const Block& b : blocks) j["blocks"].push_back(reportBlock(in.robot, b, ref));
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
  cmd->add_option("--data", args->data, "Dataset CSV (the APAL leg's columns; with --model, the model's q_<joint>, tau_<joint>)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--model", args->model,
                  "The robot: 'apal', 'leg3' (built in) or an MJCF / URDF file. Alone, prints its serial chain and base\n"
                  "parameters: rank, each identifiable combination of the standard parameters in words with its true\n"
                  "value, what no torque shows, what is regrouped; with --data, what that record identifies of them");
#ifdef EXOID_WITH_MUJOCO
  addChainSelectionOptions(*cmd, args->selection);
  cmd->add_option("--armature", args->armature,
                  "--model: joints (comma-separated, or all) given an armature parameter (a geared motor's reflected rotor\n"
                  "inertia) where the file has none, as identify --armature; the APAL leg: knee (= --knee-armature)")
      ->delimiter(',');
#endif
  cmd->add_flag("--knee-armature", args->knee_armature,
               "The APAL leg: Ia2, the knee's armature, among the parameters (as identify --knee-armature)");
  cmd->add_option("--noise-tau", args->noise_tau_Nm, "Torque noise std for the Cramer-Rao bound, N m")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  cmd->add_option("--json", args->json_out, "Write the report as JSON here");
  cmd->add_option("--reference", args->reference,
                  "Parameters the relative stds are relative to: JSON {\"parameters\": {\"Mxt\": ..}} (your leg's\n"
                  "nominal values) or an exoid sidecar / truth file (--model: a chain simulation's sidecar). Default: the\n"
                  "sidecar exoid simulate wrote beside the record (its rigid-link truth), else with --model the model\n"
                  "file's own parameters, else none (absolute stds only)")
      ->check(CLI::ExistingFile);
  addConstantsOptions(*cmd, args->constants);
  addLogInputOptions(*cmd, args->log);
  addSignalOptions(*cmd, args->signals);
  cmd->callback([args] { run(*args); });
}

}  // namespace exoid::experiments
