// `exoid identify`: identify the 10 parameters from CSV logs with one or more methods.
#include "exoid/core/atomic_file.hpp"
#include "exoid/core/format.hpp"
#include "exoid/experiments/commands/commands.hpp"
#ifdef EXOID_WITH_MUJOCO
#include "exoid/experiments/commands/robot_commands.hpp"
#include "exoid/experiments/protocol/robot_loader.hpp"
#include "exoid/experiments/report/plots.hpp"
#endif
#include "exoid/experiments/protocol/band_sensitivity.hpp"
#include "exoid/experiments/protocol/controller_io.hpp"
#include "exoid/experiments/protocol/excitation_report.hpp"
#include "exoid/experiments/protocol/fit_records.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/protocol/identify_report.hpp"
#include "exoid/experiments/protocol/stages_check.hpp"
#include "exoid/experiments/protocol/log_input.hpp"
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/experiments/report/cells.hpp"
#include "exoid/experiments/report/table.hpp"
#include "exoid/ident/signals/band.hpp"
#include "exoid/ident/estimators/band_iv.hpp"
#include "exoid/ident/leg/consistency.hpp"
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/design/identifiability.hpp"
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/estimators/segmental.hpp"
#include "exoid/ident/signals/preprocess.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <filesystem>
#include <iostream>
#include <memory>
#include <numeric>

namespace exoid::experiments {

namespace {

struct IdentifyArgs {
  std::vector<std::string> data, knee_data, both_data;  ///< several records per role are stacked
  std::string json_out;
  LogInputFlags log;
  std::vector<std::string> methods{"ls"};
  std::vector<std::string> validate;
  std::string truth;
  ConstantsFlags constants;
  ident::SignalOptions signals = defaultIdentifySignals();
  ident::MethodOptions methods_options;
  ident::IvOptions iv;
  std::string controller;  ///< JSON of the rig's controller (IDIM-IV); default: the records' metadata
  bool knee_armature = false;  ///< estimate Ia2 too
  CLI::Option* wide_box_option = nullptr;  ///< given explicitly? else sized from the data
  bool history = false;
  bool consistency = true;  ///< LS over --data: the physically consistent estimate (--no-consistency)
  bool timing = false;      ///< wall times in the table and the JSON (they differ run to run)
  ident::ConsistencyOptions consistency_options;
  std::string model;  ///< --model: a robot other than the APAL leg goes to the chain path
  std::string plot;   ///< --plot: measured against predicted torques
  std::vector<std::string> armature;  ///< --armature (chain models)
  core::ChainSelection selection;     ///< --base, --tip, --lock (chain models)
  bool moving_base_parameters = false;  ///< --moving-base-parameters (chain models)
  std::vector<std::string> stages;    ///< --stage JOINT=FILE (chain models' segmental strategy)
  int consistency_draws = 199;        ///< --consistency-draws (chain models)
  std::uint64_t consistency_seed = 1;  ///< --consistency-seed (chain models)
  CLI::App* cmd = nullptr;
};

std::vector<ident::Method> resolveMethods(const std::vector<std::string>& names) {
  std::vector<ident::Method> out;
  for (const std::string& n : names) {
    if (n == "all") {
      for (ident::Method m : ident::allMethods()) out.push_back(m);
    } else if (n == "ls-parallel" || n == "default") {
      out.push_back(ident::Method::kLs);  // the README's and the sweep's names for identify's default: LS, parallel processing
    } else if (n == "ls-exact" || n == "ls-stacked" || n == "ls-base" || n == "idim-iv-base") {
      throw CLI::ValidationError("--method", "'" + n + "' is an arm of exoid reproduce and exoid sweep (it needs the simulator's exact "
                                                     "states or records), not a method for a log; identify's are ls (= ls-parallel, the "
                                                     "default), rls, pso, rls-pso, lad, idim-iv, iv-band, all");
    } else {
      out.push_back(ident::parseMethod(n));
    }
  }
  return out;
}

// True when a stage of `m` could not identify parameter i (its value is a placeholder).
bool unidentifiable(const MethodOutcome& m, int i) {
  for (const Stage& st : m.stages) {
    for (Eigen::Index c : st.estimate.unidentifiable) {
      if (st.indices[static_cast<std::size_t>(c)] == i) return true;
    }
  }
  return false;
}

void printResults(bool timing, const std::vector<MethodOutcome>& outcomes,
                  const std::vector<std::pair<std::string, std::vector<Validation>>>& validations,
                  const std::map<std::string, ident::ParamVector>& truths) {
  std::vector<std::string> header{"param", "unit"};
  for (const auto& [name, x] : truths) header.push_back(name);
  for (const MethodOutcome& m : outcomes) header.push_back(ident::toString(m.method));
  TextTable t(header);
  for (int i = 0; i < ident::kNumParams; ++i) {
    std::vector<std::string> row{std::string(ident::paramName(i)), ident::paramInfo()[static_cast<std::size_t>(i)].unit};
    for (const auto& [name, x] : truths) row.push_back(fmt(x[i]));
    for (const MethodOutcome& m : outcomes) {
      if (unidentifiable(m, i)) {
        row.push_back("n/a (not identifiable)");
        continue;
      }
      std::string cell = fmt(m.x[i]);
      if (!truths.empty()) {
        const double tr = truths.begin()->second[i];
        if (tr != 0.0) cell += " (" + fixed(100.0 * (m.x[i] - tr) / std::abs(tr), 1) + "%)";
      }
      row.push_back(cell);
    }
    t.addRow(row);
  }
  std::vector<std::string> status{"status", ""};
  std::vector<std::string> time{"time", "s"};
  for (std::size_t k = 0; k < truths.size(); ++k) {
    status.push_back("");
    time.push_back("");
  }
  for (const MethodOutcome& m : outcomes) {
    std::string s;
    for (const Stage& st : m.stages) s += (s.empty() ? "" : "/") + std::string(ident::toString(st.estimate.summary.status));
    status.push_back(s);
    time.push_back(fmt(m.wallTime_s(), 3));
  }
  if (!outcomes.empty() && outcomes.front().knee_armature) {
    std::vector<std::string> row{"Ia2", ident::kneeArmatureInfo().unit};
    for (std::size_t k = 0; k < truths.size(); ++k) row.push_back("");
    for (const MethodOutcome& m : outcomes) row.push_back(m.knee_armature ? fmt(*m.knee_armature) : "-");
    t.addRow(row);
  }
  t.addRow(status);
  if (timing) t.addRow(time);  // wall times differ run to run: only when asked (--timing)
  t.print(std::cout);
  if (!truths.empty()) std::cout << "(percent: relative error against '" << truths.begin()->first << "')\n";
  for (const MethodOutcome& m : outcomes) {
    for (const Stage& st : m.stages) {
      const auto& e = st.estimate;
      std::cout << ident::toString(m.method) << " [" << st.name << "]: " << e.summary.message;
      if (e.rank) std::cout << "; rank " << *e.rank;
      if (e.condition_number) std::cout << "; condition " << fmt(*e.condition_number, 4);
      if (e.optimality_gap_rel) std::cout << "; L1 cost " << fmt(e.l1_cost, 8) << ", optimality gap " << fmt(100.0 * *e.optimality_gap_rel, 3) << " %";
      if (e.optimality_gap_box_rel) std::cout << " (over its box: " << fmt(100.0 * *e.optimality_gap_box_rel, 3) << " %)";
      std::cout << '\n';
    }
  }
  for (const auto& [file, vals] : validations) {
    TextTable v({"validation: " + file, "hip |e| mean +- std (N m)", "hip rms", "knee |e| mean +- std (N m)", "knee rms"});
    for (std::size_t k = 0; k < outcomes.size(); ++k) {
      const Validation& val = vals[k];
      v.addRow({ident::toString(outcomes[k].method), fixed(val.hip.mean_abs) + " +- " + fixed(val.hip.std_abs),
                fixed(val.hip.rms), fixed(val.knee.mean_abs) + " +- " + fixed(val.knee.std_abs), fixed(val.knee.rms)});
    }
    std::cout << '\n';
    v.print(std::cout);
  }
}

// One role's records (--data, --knee-data or --both-data), read and processed each on its own.
struct Role {
  std::vector<std::string> files;
  std::vector<ident::Dataset> data;
  ident::RecordRows rows;  ///< the records' rows stacked
  /// Each record's processing as used: the options with every choice made from the data.
  std::vector<ident::SignalOptions> signals;
  std::vector<std::optional<ident::BandChoice>> bands;  ///< the band chosen from each record, if any
  nlohmann::json processing = nlohmann::json::object();  ///< each record's processing as used, by file
};

// The command line's combinations: one kind of input, what each method needs of it.
void checkArguments(const IdentifyArgs& a, const std::vector<ident::Method>& methods) {
  if (std::find(a.methods.begin(), a.methods.end(), "ls-parallel") != a.methods.end() && a.signals.processing != ident::Processing::kParallel) {
    throw CLI::ValidationError("--method ls-parallel", "is LS with the parallel processing; --processing paper contradicts it (use --method ls)");
  }
  const bool single = !a.data.empty();
  const bool segmental = !a.knee_data.empty() || !a.both_data.empty();
  if (single == segmental) {
    throw CLI::ValidationError("identify", "give either --data FILE (repeatable), or --knee-data FILE and --both-data FILE (segmental strategy)");
  }
  if (segmental && (a.knee_data.empty() || a.both_data.empty())) {
    throw CLI::ValidationError("identify", "the segmental strategy needs both --knee-data and --both-data");
  }
  if (segmental && a.knee_armature) {
    throw CLI::ValidationError("--knee-armature", "needs --data: a record where the hip moves, fitted with both equations (with "
                               "the hip fixed the armature's column is Js's, and Js enters the hip equation without it)");
  }
  a.methods_options.validate();
  a.iv.validate();
  const bool iv = std::find(methods.begin(), methods.end(), ident::Method::kIdimIv) != methods.end();
  if (iv && a.signals.processing != ident::Processing::kParallel) {
    throw CLI::ValidationError("--method idim-iv", "needs '--processing parallel' (the default): its instruments are processed like the measured rows");
  }
  if (iv && (a.data.size() > 1 || a.knee_data.size() > 1 || a.both_data.size() > 1)) {
    throw CLI::ValidationError("--method idim-iv", "takes one record per role for now (its instruments simulate each record "
                               "under its controller); stack records with the other methods");
  }
  const bool band_iv = std::find(methods.begin(), methods.end(), ident::Method::kIvBand) != methods.end();
  if (band_iv && (segmental || a.signals.processing != ident::Processing::kParallel)) {
    throw CLI::ValidationError("--method iv-band", "needs --data (both equations of each record) and the parallel processing "
                               "(the default) for now");
  }
}

// Records that say their own Lt must agree with the one used.
void checkThighLengths(const IdentifyArgs& a, const LogInput& log, const ident::LegConstants& c, const Role& primary,
                       const Role& knee) {
  for (const Role* role : {&primary, &knee}) {
    for (std::size_t k = 0; k < role->files.size(); ++k) {
      if (const auto lt = role->data[k].metadata("thigh_length_m"); lt && !a.constants.thigh_length_m && !log.thigh_length_m) {
        if (std::abs(std::stod(*lt) - c.thigh_length_m) > 1e-12) {
          throw std::invalid_argument(role->files[k] + ": its thigh_length_m " + *lt + " differs from " + primary.files.front() +
                                      "'s " + fmt(c.thigh_length_m) + "; give --thigh-length");
        }
      }
    }
  }
}

// Each role's records processed and stacked, with how well they excite the parameters.
void processRoles(const LogInput& log, const ident::Robot& robot, const ident::SignalOptions& signals, bool segmental, Role& primary,
                  Role& knee) {
  // The band is the leg's own (X): an optional term (the knee armature) is judged on the same rows as without it.
  const ident::Robot leg = ident::twoLinkLeg(*robot.two_link);
  for (Role* role : {&knee, &primary}) {
    if (role->files.empty()) continue;
    for (std::size_t k = 0; k < role->files.size(); ++k) {
      std::cout << "record " << role->files[k] << ": " << samplingSummary(role->data[k], log.csv) << '\n';
    }
    // The segmental knee record's hip is locked (no hip torque): its band is judged by its knee equation.
    ident::BandRule rule;
    rule.first_moving_joint = role == &knee ? 1 : 0;
    FitRecords fit = processFitRecords(role->files, role->data, robot, signals, rule, &leg);
    role->signals = std::move(fit.signals);
    role->bands = std::move(fit.bands);
    role->processing = std::move(fit.json);
    role->rows = ident::stackRecords(fit.rows);
    const bool knee_role = role == &knee;
    // X's ten parameters (a fitted knee armature's column left out), or the knee role's shank columns.
    const int first = knee_role ? ident::kShankFirst : 0, count = knee_role ? ident::kGroupSize : ident::kNumParams;
    const Eigen::MatrixXd H = knee_role ? Eigen::MatrixXd(role->rows.jointW(1).middleCols(first, count)) : Eigen::MatrixXd(role->rows.W.leftCols(count));
    const std::vector<std::string> names(robot.names().begin() + first, robot.names().begin() + first + count);
    ident::LsOptions lo;
    lo.max_condition = std::numeric_limits<double>::max();
    std::cout << describe(excitationOf(ident::solveLeastSquares(H, knee_role ? role->rows.jointY(1) : role->rows.y, lo), names),
                          knee_role ? "the knee records (shank columns)" : segmental ? "the both-joint records" : "the records",
                          "`exoid identifiability --data FILE` says what motion would separate them; `exoid excite` designs one")
              << '\n';
  }
}

// The PSO baseline's box from the data, unless --wide-box was given.
void sizePsoBox(const IdentifyArgs& a, const std::vector<ident::Method>& methods, bool segmental, const Role& primary,
                const Role& knee, ident::MethodOptions& mo) {
  if (std::find(methods.begin(), methods.end(), ident::Method::kPso) != methods.end() && a.wide_box_option &&
      a.wide_box_option->count() == 0) {
    Eigen::VectorXd ls = ident::solveLeastSquares(primary.rows.W.leftCols(ident::kNumParams), primary.rows.y, mo.ls).x;
    if (segmental) {
      const Eigen::MatrixXd H = knee.rows.jointW(1).middleCols(ident::kShankFirst, ident::kGroupSize);
      const Eigen::VectorXd knee_ls = ident::solveLeastSquares(H, knee.rows.jointY(1), mo.ls).x;
      ls.conservativeResize(ls.size() + knee_ls.size());
      ls.tail(knee_ls.size()) = knee_ls;
    }
    mo.wide_box_half_width = ident::psoHalfWidthFromLs(ls);
    std::cout << "PSO box: +-" << fmt(mo.wide_box_half_width, 3) << " in every parameter (10 x the largest |LS estimate|; "
              << "--wide-box sets it)\n";
  }

}

// Why one method's result must not be used (empty: usable), each reason named.
std::vector<std::string> problemsOf(const MethodOutcome& m) {
  std::vector<std::string> out;
  const std::string method(ident::toString(m.method));
  if (!m.usable()) out.push_back(method + ": " + m.problems());
  for (const std::string& v : m.implausible) out.push_back(method + ": physically implausible: " + v);
  // On a bound the box chose the value, not the data: the paper's RLS box as much as PSO's wide one.
  for (const BoundHit& h : boxBoundHits(m)) {
    out.push_back(method + " [" + h.stage + "]: " + describe(h) + ": the box does not hold the cost's optimum");
  }
  return out;
}



// The band sensitivity of LS over --data (its unconstrained estimate, its reported errors).
std::optional<BandSensitivity> lsBandSensitivity(const IdentifyArgs& a, const Role& primary, const ident::Robot& robot,
                                                 const std::vector<MethodOutcome>& outcomes) {
  for (auto m = outcomes.rbegin(); m != outcomes.rend(); ++m) {  // the last LS (ls, ls-parallel)
    if (m->method != ident::Method::kLs || !m->consistency) continue;
    const std::optional<BandRefit> refit =
        refitInAWiderBand(primary.data, primary.signals, primary.bands, a.signals.derivative_cutoff_from_data, robot, primary.rows);
    if (!refit) return std::nullopt;
    return bandSensitivity(*refit, robot, m->consistency->unconstrained, m->consistency->std_err);
  }
  return std::nullopt;
}

void printErrors(ident::Method m, const ident::ReportedErrors& e, const char* how) {
  std::cout << ident::toString(m) << ": standard errors (the larger of Newey-West from the residuals and a jackknife "
            << "over blocks of the records and, from 3 records, over whole records" << how << "; * the jackknife's):";
  for (Eigen::Index i = 0; i < e.reported.size(); ++i) {
    std::cout << ' ' << ident::paramName(static_cast<int>(i)) << ' ' << fmt(e.reported[i], 3) << (e.from_jackknife[static_cast<std::size_t>(i)] ? "*" : "");
  }
  std::cout << '\n';
}

void printConsistency(const std::vector<MethodOutcome>& outcomes) {
  for (const MethodOutcome& m : outcomes) {
    if (m.segmental_errors) printErrors(m.method, *m.segmental_errors, ", stage by stage with what the knee stage carries into the hip's");
    if (!m.consistency) continue;
    const ConsistencyStep& cs = *m.consistency;
    if (!m.segmental_errors) printErrors(m.method, cs.errors, "");
    if (!cs.fit.constrained) {
      std::cout << ident::toString(m.method) << ": physically consistent (friction >= 0, Js >= 0, Jt >= Js, "
                << "(Jt - Js) Js >= Lt^2 (Mxs^2 + Mys^2))\n";
      continue;
    }
    for (const std::string& v : cs.withinNoise()) {
      std::cout << ident::toString(m.method) << ": " << v << ": consistent with the bound within "
                << fmt(cs.significance_sigmas, 3) << " standard errors\n";
    }
    std::cout << ident::toString(m.method) << ": the table gives the physically consistent estimate ("
              << (m.segmental_errors ? "the nearest in its standard errors" : "constrained least squares") << "); unconstrained:";
    for (Eigen::Index i = 0; i < cs.unconstrained.size(); ++i) {
      std::cout << ' ' << ident::paramName(static_cast<int>(i)) << ' ' << fmt(cs.unconstrained[i], 5);
    }
    std::cout << '\n';
  }
}

// Each record's sampling as read and used, by file.
nlohmann::json rolesSamplingJson(const Role& primary, const Role& knee) {
  nlohmann::json sampling = nlohmann::json::object();
  for (const Role* role : {&knee, &primary}) {
    for (std::size_t k = 0; k < role->files.size(); ++k) sampling[role->files[k]] = samplingJson(role->data[k]);
  }
  return sampling;
}

// Each method's outcome, problems, validation and parameter errors, by method.
nlohmann::json methodsJson(const IdentifyArgs& a, const std::vector<MethodOutcome>& outcomes,
                           const std::vector<std::pair<std::string, std::vector<Validation>>>& validations,
                           const std::map<std::string, ident::ParamVector>& truths) {
  nlohmann::json methods = nlohmann::json::object();
  for (std::size_t k = 0; k < outcomes.size(); ++k) {
    nlohmann::json mj = toJson(outcomes[k], a.history);
    mj["problems"] = problemsOf(outcomes[k]);
    for (const auto& [file, vals] : validations) mj["validation"][file] = toJson(vals[k]);
    for (const auto& [name, x] : truths) mj["parameter_error"][name] = toJson(ident::paramError(outcomes[k].x, x));
    methods[ident::toString(outcomes[k].method)] = mj;
  }
  return methods;
}

void writeIdentifyJson(const IdentifyArgs& a, const LogInput& log, const ident::LegConstants& c, const std::string& constants_origin,
                       const Role& primary, const Role& knee, const ident::MethodOptions& mo,
                       const std::vector<MethodOutcome>& outcomes,
                       const std::vector<std::pair<std::string, std::vector<Validation>>>& validations,
                       const std::map<std::string, ident::ParamVector>& truths,
                       const std::optional<BandSensitivity>& sensitivity, const ident::Robot& robot,
                       const ident::Determination& determination, const nlohmann::json& reports, const std::vector<std::string>& problems) {
  IdentifyEnvelope envelope{{{"name", "apal_leg"}, {"joints", robot.jointNames()}, {"parameters", "X, the paper's 10 (the 2-link leg of the constants)"}},
                            primary.files, {}, a.validate, rolesSamplingJson(primary, knee), log.profile, a.signals, mo, problems};
  for (const std::string& file : knee.files) envelope.stages.emplace_back("knee", file);
  nlohmann::json j = toJson(envelope);
  j["processing_per_record"] = knee.processing;
  j["processing_per_record"].update(primary.processing);
  // Whether the base-motion terms were in the first record's rows (processing_per_record: each record's, and why).
  j["base_terms_used"] = usesBaseMotion(primary.data.front(), primary.signals.front());
  j["constants"] = {{"thigh_length_m", c.thigh_length_m}, {"gravity_mps2", c.gravity_mps2}, {"origin", constants_origin}};
  j["methods"] = methodsJson(a, outcomes, validations, truths);
  // The first method's estimate at top level, for tools that expect one answer.
  j["method"] = ident::toString(outcomes.front().method);
  j["parameters"] = paramsJson(outcomes.front().x);
  std::vector<std::string> files = knee.files;  // the determination's records: the knee role's first when segmental
  files.insert(files.end(), primary.files.begin(), primary.files.end());
  j["determination"] = determinationJson(robot, determination, files);
  for (const auto& [name, report] : reports.items()) j[name] = report;  // optional_terms, against_one_fit
  if (sensitivity) j["band_sensitivity"] = toJson(*sensitivity);
  if (!a.timing) j = withoutWallTimes(j);  // same input, same bytes
  if (!truths.empty()) {
    j["truth"] = nlohmann::json::object();
    for (const auto& [name, x] : truths) j["truth"][name] = paramsJson(x);
  }
  writeJsonFile(a.json_out, j);
}

#ifdef EXOID_WITH_MUJOCO
// A chain's arguments, the APAL leg's spelling read as every leg's (as legArguments reads a chain's
// for the APAL leg): --knee-data FILE --both-data FILE is --stage knee=FILE --data FILE;
// --knee-armature is --armature knee.
IdentifyArgs chainArguments(IdentifyArgs a) {
  if (!a.knee_data.empty() || !a.both_data.empty()) {
    if (!a.data.empty() || !a.stages.empty()) {
      throw CLI::ValidationError(a.knee_data.empty() ? "--both-data" : "--knee-data",
                                 "give the stages once: --stage knee=FILE with --data, or --knee-data with --both-data");
    }
    if (a.knee_data.empty() || a.both_data.empty()) throw CLI::ValidationError("identify", "the segmental strategy needs both --knee-data and --both-data");
    for (const std::string& file : a.knee_data) a.stages.push_back("knee=" + file);
    a.data = a.both_data;
    a.knee_data.clear();
    a.both_data.clear();
  }
  if (a.knee_armature && std::find(a.armature.begin(), a.armature.end(), "knee") == a.armature.end()) a.armature.push_back("knee");
  return a;
}

// --model naming a robot other than the APAL leg: its base parameters by least squares (and the
// consistent estimate). The APAL leg's constants are the model's own: refused by name, never ignored.
bool runChainModel(const IdentifyArgs& given) {
  if (given.model.empty() && !given.selection.empty()) throw CLI::ValidationError("--base/--tip/--lock", "pick a chain out of --model FILE: give --model");
  if (given.model.empty() || isApalLeg(given.model, given.selection)) return false;
  for (const char* apal_only : {"--thigh-length", "--gravity"}) {
    if (given.cmd->count(apal_only) > 0) {
      throw CLI::ValidationError(apal_only, "is the APAL leg's constant; a chain model's (--model " + given.model + ") come from its file");
    }
  }
  const IdentifyArgs a = chainArguments(given);
  std::vector<ident::Method> methods;
  for (ident::Method m : resolveMethods(a.methods)) {
    if ((m == ident::Method::kIvBand || m == ident::Method::kIdimIv) && (!a.stages.empty() || a.signals.processing != ident::Processing::kParallel)) {
      throw CLI::ValidationError(std::string("--method ") + ident::toString(m),
                                 "needs one fit of --data (no --stage) and the parallel processing (its instruments are processed like the rows)");
    }
    methods.push_back(m);
  }
  ChainIdentifyArgs c;
  c.model = a.model;
  c.data = a.data;
  for (const std::string& s : a.stages) c.stages.push_back(parseStage(s));
  c.validate = a.validate;
  c.plot = a.plot;
  c.armature = a.armature;
  c.selection = a.selection;
  c.moving_base_parameters = a.moving_base_parameters;
  c.truth = a.truth;
  c.json_out = a.json_out;
  c.log = a.log;
  c.signals = a.signals;
  c.consistency = a.consistency;
  c.significance_sigmas = a.consistency_options.significance_sigmas;
  c.consistency_draws = a.consistency_draws;
  c.consistency_seed = a.consistency_seed;
  c.max_condition = a.methods_options.ls.max_condition;
  c.methods = methods;
  c.method_options = a.methods_options;
  c.wide_box_given = a.wide_box_option && a.wide_box_option->count() > 0;
  c.controller = a.controller;
  a.iv.validate();
  c.iv = a.iv;
  c.timing = a.timing;
  c.history = a.history;
  if (std::find(methods.begin(), methods.end(), ident::Method::kIdimIv) == methods.end() && !a.controller.empty()) {
    throw CLI::ValidationError("--controller", "is IDIM-IV's (--method idim-iv); no method given uses it");
  }
  identifyChain(c);
  return true;
}
#endif

// The APAL leg's arguments, a chain's spelling read as its own (parseStage, apalKneeArmature):
// --stage knee=FILE with --data is --knee-data FILE --both-data; --armature knee is --knee-armature.
IdentifyArgs legArguments(IdentifyArgs a) {
  if (apalKneeArmature(a.armature)) a.knee_armature = true;
  a.armature.clear();
  if (a.stages.empty()) return a;
  if (!a.knee_data.empty() || !a.both_data.empty()) {
    throw CLI::ValidationError("--stage", "give the APAL leg's stages once: --stage knee=FILE with --data, or --knee-data with --both-data");
  }
  for (const std::string& s : a.stages) {
    const auto [joint, file] = parseStage(s);
    if (joint != "knee") {
      throw CLI::ValidationError("--stage", "the APAL leg's first stage is knee=FILE (a record with the hip locked), its last --data; got '" + s + "'");
    }
    a.knee_data.push_back(file);
  }
  a.both_data = a.data;
  a.data.clear();
  a.stages.clear();
  return a;
}

// What a chain model's identify takes and the APAL leg's does not.
void checkLegArguments([[maybe_unused]] const IdentifyArgs& a) {
#ifdef EXOID_WITH_MUJOCO
  if (a.moving_base_parameters) throw CLI::ValidationError("--moving-base-parameters", "is for a chain model (--model leg3|FILE); the APAL leg's X is the paper's");
  for (const char* chain_only : {"--consistency-draws", "--consistency-seed"}) {
    if (a.cmd->count(chain_only) > 0) {
      throw CLI::ValidationError(chain_only, "is a chain model's (--model leg3|FILE); the APAL leg judges each of its four conditions by its "
                                             "standard errors (--significance)");
    }
  }
#endif
}

// The records of both roles read, the leg's constants resolved, each record processed.
struct LegRecords {
  Role primary, knee;  ///< --data or --both-data; --knee-data
  ident::LegConstants c;
  ident::Robot robot;  ///< the 2-link leg of c (with the knee armature when asked)
  std::string constants_origin;
  /// What the records' motion determines: one fit of every parameter from both equations; or,
  /// segmental, the knee equation's parameters from the knee records and the rest from the
  /// both-joint records' hip equation.
  ident::Determination determination;
};

ident::Determination legDetermination(const LegRecords& r, bool segmental) {
  std::vector<int> all(static_cast<std::size_t>(r.robot.parameters()));
  std::iota(all.begin(), all.end(), 0);
  if (!segmental) return ident::determination(r.robot, r.primary.data, r.primary.rows, all);
  // The knee records' knee equation fits the knee's parameters; then the both-joint records' hip equation the rest.
  const std::vector<int>& knee_params = r.robot.joint_columns[1];
  std::vector<int> hip_params;
  for (int i : all) {
    if (std::find(knee_params.begin(), knee_params.end(), i) == knee_params.end()) hip_params.push_back(i);
  }
  return ident::determination(r.robot, {{&r.knee.data, &r.knee.rows, {1}, ident::parameterDirections(r.robot, knee_params)},
                                        {&r.primary.data, &r.primary.rows, {0}, ident::parameterDirections(r.robot, hip_params)}});
}

LegRecords readLegRecords(const IdentifyArgs& a, const LogInput& log) {
  const bool single = !a.data.empty();
  LegRecords r;
  r.primary.files = single ? a.data : a.both_data;
  r.knee.files = a.knee_data;
  for (Role* role : {&r.primary, &r.knee}) {
    for (const std::string& f : role->files) role->data.push_back(readLog(f, log));
  }
  r.c = resolveConstants(a.constants, r.primary.data.front(), &r.constants_origin, log.thigh_length_m, log.gravity_mps2);
  checkThighLengths(a, log, r.c, r.primary, r.knee);
  std::cout << "constants: Lt " << fmt(r.c.thigh_length_m) << " m, g " << fmt(r.c.gravity_mps2) << " m/s^2 (" << r.constants_origin << ")\n";
  r.robot = ident::twoLinkLeg(r.c, a.knee_armature);
  processRoles(log, r.robot, a.signals, !single, r.primary, r.knee);
  r.determination = legDetermination(r, !single);
  if (const std::string p = undeterminedProblem(r.robot, r.determination); !p.empty()) std::cout << p << '\n';
  return r;
}

// IDIM-IV's closed-loop descriptions of the records (the knee role's when segmental).
struct ClosedLoopRecords {
  ident::ClosedLoopRecord primary, knee;
};

ClosedLoopRecords closedLoopRecords(const IdentifyArgs& a, const LegRecords& r) {
  const bool segmental = a.data.empty();
  ClosedLoopRecords cl;
  cl.primary = closedLoopRecord(r.primary.data.front(), r.primary.files.front(), r.primary.rows, r.primary.signals.front(), a.controller);
  if (segmental) cl.knee = closedLoopRecord(r.knee.data.front(), r.knee.files.front(), r.knee.rows, r.knee.signals.front(), a.controller, 1);
  return cl;
}

MethodOutcome identifyBy(ident::Method m, const IdentifyArgs& a, const LegRecords& r, const ClosedLoopRecords& cl,
                         const ident::MethodOptions& mo) {
  const bool single = !a.data.empty();
  const Role& primary = r.primary;
  if (m == ident::Method::kIvBand) {
    // Instruments from each record's angles low-passed at its motion's bandwidth, processed in its band.
    std::vector<ident::BandIvRows> rows;
    for (std::size_t k = 0; k < primary.data.size(); ++k) {
      const double fm = primary.bands[k] ? primary.bands[k]->motion_bandwidth_hz : ident::motionBandwidth(primary.data[k]);
      rows.push_back(ident::bandIvRows(primary.data[k], r.robot, primary.signals[k], fm));
    }
    return identifyAll(ident::solveBandIv(rows, mo.ls), a.knee_armature);
  }
  if (m == ident::Method::kIdimIv) {
    // Each record's instruments are processed as its measured rows were (its band).
    return single ? identifyAllIdimIv(r.robot, cl.primary, a.iv) : identifySegmentedIdimIv(r.robot, cl.knee, cl.primary, a.iv);
  }
  return single ? identifyAll(m, primary.rows, mo) : identifySegmented(r.robot, m, r.knee.rows, primary.rows, mo);
}

// Every --validate record, processed in the band the fit used (its first record's, so the errors
// are the fit's yardstick), against every method's estimate.
std::vector<std::pair<std::string, std::vector<Validation>>> validateOutcomes(const IdentifyArgs& a, const LogInput& log,
                                                                              const LegRecords& r,
                                                                              const std::vector<MethodOutcome>& outcomes) {
  std::vector<std::pair<std::string, std::vector<Validation>>> validations;
  for (const std::string& file : a.validate) {
    ident::RecordRows rv;
    try {
      rv = ident::processRecord(readLog(file, log), r.robot, r.primary.signals.front());
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(file + ": " + e.what());
    }
    std::vector<Validation> v;
    for (const MethodOutcome& m : outcomes) v.push_back(validate(rv, m.x, m.knee_armature.value_or(0.0)));
    validations.emplace_back(file, std::move(v));
  }
  return validations;
}

// The knee armature tested on the --data (or --both-data) records (identification.hpp): when one fit
// of them is physically implausible.
ArmatureTest kneeArmatureTest(const LegRecords& r, const ident::MethodOptions& mo, double significance_sigmas) {
  const ident::Robot with = ident::twoLinkLeg(r.c, true);
  std::vector<ident::RecordRows> rows;
  for (std::size_t k = 0; k < r.primary.data.size(); ++k) rows.push_back(ident::processRecord(r.primary.data[k], with, r.primary.signals[k]));
  return armatureTest(with, rows, {"knee"}, significance_sigmas, mo.ls.max_condition);
}

// The segmental strategy against one fit of the both-joint records (stages_check.hpp), as a
// chain's stages are judged: printed, in the JSON, and exit 3 when that one fit is physically
// implausible (its own identify would exit 3), naming --knee-armature when the records show one.
struct SegmentalCheck {
  nlohmann::json json;
  std::string problem;
};

SegmentalCheck againstOneFit(const IdentifyArgs& a, const LegRecords& r, const ident::MethodOptions& mo, const std::vector<MethodOutcome>& outcomes) {
  SegmentalCheck out;
  const auto ls = std::find_if(outcomes.begin(), outcomes.end(), [](const MethodOutcome& m) { return m.method == ident::Method::kLs; });
  const ident::RecordRows& rows = r.primary.rows;
  const auto not_judged = [&out](const std::string& why) {
    out.json = notJudged(why);
    return out;
  };
  if (ls == outcomes.end() || !ls->segmental_errors) return not_judged("no least-squares estimate of the stages with its errors (--method without ls, or LS not usable)");
  MethodOutcome one = identifyAll(ident::Method::kLs, rows, mo);
  const Eigen::VectorXd x = one.stages.front().estimate.x;
  if (!ident::usable(one.stages.front().estimate.summary.status)) return not_judged("those records alone do not determine every parameter");
  if (explainedToRounding(rows.W, rows.y, x)) return not_judged("the model explains them to rounding: no term is left out");
  // The one fit's reported errors: its consistency step's, or computed alone without it.
  if (a.consistency) applyConsistency(one, rows, r.c, a.consistency_options);
  const Eigen::VectorXd errors = one.consistency ? one.consistency->std_err : legReportedErrors(rows, x).reported;
  if (!errors.allFinite() || !ls->segmental_errors->reported.allFinite()) return not_judged("the errors are not finite");
  const Eigen::VectorXd stages = ls->consistency ? ls->consistency->unconstrained : Eigen::VectorXd(ls->x);
  StagesAgainstOneFit c = compareStagesWithOneFit(stages, ls->segmental_errors->reported, x, errors, a.consistency_options.significance_sigmas);
  c.consistency_judged = a.consistency;
  for (const std::string& v : one.implausible) c.one_fit_inconsistency += (c.one_fit_inconsistency.empty() ? "is physically implausible: " : "; ") + v;
  std::cout << wrapped(describe(c, r.robot.names())) << '\n';
  out.json = toJson(c, r.robot.names());
  if (c.one_fit_inconsistency.empty()) return out;
  out.problem = stagesHidProblem(c, kneeArmatureTest(r, mo, a.consistency_options.significance_sigmas).hint());
  return out;
}

#ifdef EXOID_WITH_MUJOCO
// --plot: the first method's estimate on the first --validate record (else the first fit record),
// as a chain's identify draws LS's.
void plotLegFit(const IdentifyArgs& a, const LogInput& log, const LegRecords& r, const MethodOutcome& m) {
  const bool validation = !a.validate.empty();
  const ident::RecordRows shown =
      ident::processRecord(validation ? readLog(a.validate.front(), log) : r.primary.data.front(), r.robot, r.primary.signals.front());
  Eigen::VectorXd theta(r.robot.parameters());
  theta.head(ident::kNumParams) = m.x;
  if (theta.size() > ident::kNumParams) theta[ident::kKneeArmature] = m.knee_armature.value_or(0.0);
  plotTorqueFit(a.plot, r.robot.jointNames(), shown, theta,
                "APAL leg, " + std::string(ident::toString(m.method)) + ": " +
                    (validation ? "validation record " + a.validate.front() : "fit record " + r.primary.files.front()));
}
#endif

void run(const IdentifyArgs& given) {
#ifdef EXOID_WITH_MUJOCO
  if (runChainModel(given)) return;
#endif
  const IdentifyArgs a = legArguments(given);
  checkLegArguments(a);
  const std::vector<ident::Method> methods = resolveMethods(a.methods);
  checkArguments(a, methods);
  if (!a.json_out.empty()) core::checkOutputWritable(a.json_out);  // before the work, not after it
  if (!a.plot.empty()) core::prepareOutputFile(a.plot);
  const bool single = !a.data.empty(), segmental = !single;
  const bool iv = std::find(methods.begin(), methods.end(), ident::Method::kIdimIv) != methods.end();
  std::map<std::string, ident::ParamVector> truths;
  if (!a.truth.empty()) truths = readTruthFile(a.truth);

  const LogInput log = resolveLogInput(a.log, a.signals.filter ? a.signals.cutoff_hz : 0.0);
  const LegRecords r = readLegRecords(a, log);
  // IDIM-IV's closed-loop descriptions, read before any work so a missing one fails fast.
  const ClosedLoopRecords cl = iv ? closedLoopRecords(a, r) : ClosedLoopRecords{};
  ident::MethodOptions mo = a.methods_options;
  sizePsoBox(a, methods, segmental, r.primary, r.knee, mo);

  std::vector<MethodOutcome> outcomes;
  for (ident::Method m : methods) outcomes.push_back(identifyBy(m, a, r, cl, mo));
  if (a.consistency) {
    for (MethodOutcome& m : outcomes) {
      if (m.method != ident::Method::kLs) continue;
      if (single) applyConsistency(m, r.primary.rows, r.c, a.consistency_options);
      if (segmental && m.segmental_errors) applySegmentalConsistency(m, r.c, a.consistency_options);
    }
  }
  std::optional<ArmatureTest> armature;
  const bool implausible = std::any_of(outcomes.begin(), outcomes.end(), [](const MethodOutcome& m) { return !m.implausible.empty(); });
  if (single && !a.knee_armature && implausible) armature = kneeArmatureTest(r, mo, a.consistency_options.significance_sigmas);
  const std::optional<BandSensitivity> sensitivity = single ? lsBandSensitivity(a, r.primary, r.robot, outcomes) : std::nullopt;
  const std::vector<std::pair<std::string, std::vector<Validation>>> validations = validateOutcomes(a, log, r, outcomes);

  printResults(a.timing, outcomes, validations, truths);
  printConsistency(outcomes);
  if (sensitivity) {
    for (const std::string& line : describe(*sensitivity)) std::cout << line << '\n';
  }
  if (armature && !armature->joints.empty()) std::cout << "implausible: " << armature->hint() << '\n';
  const SegmentalCheck against = segmental ? againstOneFit(a, r, mo, outcomes) : SegmentalCheck{};
#ifdef EXOID_WITH_MUJOCO
  if (!a.plot.empty()) plotLegFit(a, log, r, outcomes.front());
#endif
  // Why the result must not be used (exit code 3), each reason named.
  std::vector<std::string> problems;
  if (const std::string p = undeterminedProblem(r.robot, r.determination); !p.empty()) problems.push_back(p);
  for (const MethodOutcome& m : outcomes) {
    for (const std::string& p : problemsOf(m)) problems.push_back(p);
  }
  if (armature && !armature->joints.empty()) problems.push_back(armature->hint());
  if (!against.problem.empty()) problems.push_back(against.problem);
  if (!a.json_out.empty()) {
    nlohmann::json reports = nlohmann::json::object();
    if (!against.json.is_null()) reports["against_one_fit"] = against.json;
    if (armature) reports["optional_terms"] = {{"armature", armature->json}, {"hint", armature->hint()}};
    writeIdentifyJson(a, log, r.c, r.constants_origin, r.primary, r.knee, mo, outcomes, validations, truths, sensitivity, r.robot, r.determination,
                      reports, problems);
  }
  if (!problems.empty()) throw UnusableResult(core::joined(problems, "; "));
}

}  // namespace

namespace {

// Options in CLI11's help: grouped by name, the groups in the order they first appear, so each
// function below adds its group's options in their listed order.

// The records, the methods and what they need; the yardsticks (--validate, --truth).
void addInputOptions(CLI::App& cmd, IdentifyArgs& args) {
  cmd.add_option("--data", args.data, "Dataset CSV: identify all 10 parameters from both equations (repeatable)")
      ->check(CLI::ExistingFile)->group("Input");
  cmd.add_option("--knee-data", args.knee_data, "Segmental step 1: knee-only record, hip fixed (repeatable)")
      ->check(CLI::ExistingFile)->group("Input");
  cmd.add_option("--both-data", args.both_data, "Segmental step 2: record where both joints swing (repeatable)")
      ->check(CLI::ExistingFile)->group("Input");
  cmd.add_option("--method", args.methods,
                 "ls (also ls-parallel: LS with the default parallel processing), rls, pso, rls-pso, lad, idim-iv, iv-band, or all\n"
                 "(= all but idim-iv and iv-band) (repeatable).\n"
                 "iv-band: instrumental variables from the motion's band, no controller model needed. idim-iv needs the\n"
                 "records' q_hip_ref, q_knee_ref columns (a chain's: q_<joint>_ref) and their controller (--controller, or\n"
                 "the '# controller_*' metadata exoid simulate writes)")
      ->capture_default_str()->delimiter(',')->group("Input");
  cmd.add_option("--controller", args.controller,
                 "IDIM-IV: JSON of the rig's controller, one gain per joint: {\"kp\": [..], \"kd\": [..], \"ki\": [..],\n"
                 "\"derivative\": \"error_difference\"|\"measured_velocity\", \"derivative_cutoff_hz\": .., \"integral_limit_Nm\": ..,\n"
                 "\"feedforward\": \"model\"|\"none\", \"actuator_bandwidth_hz\": .., \"locked\": [joints]} (u = ff + kp e + ki int(e)\n"
                 "+ kd de, e = q_ref - q; de the error's filtered difference, or qd_ref - qd with the measured velocity);\n"
                 "default: the records' metadata")
      ->check(CLI::ExistingFile)->group("Input");
  cmd.add_option("--validate", args.validate, "Validation record(s): torque error per joint (repeatable)")
      ->check(CLI::ExistingFile)->group("Input");
  cmd.add_option("--truth", args.truth, "Truth JSON ({\"parameters\": {...}} or a simulation sidecar): parameter errors")
      ->check(CLI::ExistingFile)->group("Input");
}

// The knee armature, IDIM-IV's stopping rule, and how physical consistency judges the result.
void addIdentificationOptions(CLI::App& cmd, IdentifyArgs& args) {
  cmd.add_flag("--knee-armature", args.knee_armature,
               "Also estimate Ia2, the knee's armature (reflected rotor/actuator inertia on its own diagonal, kg m^2): "
               "Ia2 qdd2 joins the knee equation only; needs --data (both equations of a record where the hip moves)")
      ->group("Identification");
  cmd.add_option("--iv-tolerance", args.iv.step_tolerance, "IDIM-IV: stop when every step < this many standard errors, (0, 1)")
      ->capture_default_str()->group("Identification");
  cmd.add_option("--iv-max-iterations", args.iv.max_iterations, "IDIM-IV: iteration limit, >= 1")
      ->capture_default_str()->group("Identification");
  cmd.add_flag("!--no-consistency", args.consistency,
               "LS: report the unconstrained estimate and judge it by the plain plausibility rule, instead of the\n"
               "physically consistent estimate (friction >= 0, Js >= 0, Jt >= Js, (Jt - Js) Js >= Lt^2 (Mxs^2 + Mys^2))\n"
               "whose violations count only beyond --significance standard errors (segmental: the nearest consistent\n"
               "estimate in the metric of its reported covariance)")
      ->group("Identification");
  cmd.add_option("--significance", args.consistency_options.significance_sigmas,
                 "Standard errors beyond which a violated physical condition is significant (exit code 3); a chain model:\n"
                 "the level 1 - Phi(s) its consistency verdict's draws are judged by (--consistency-draws)")
      ->check(positiveNumber())->capture_default_str()->group("Identification");
}

void addOutputOptions(CLI::App& cmd, IdentifyArgs& args) {
  cmd.add_option("--json", args.json_out, "Write the results as JSON here (atomically)")->group("Output");
  cmd.add_flag("--timing", args.timing,
               "Wall times of each method in the JSON, and in the APAL leg's table (without it, the same input gives the same\n"
               "bytes)")
      ->group("Output");
  cmd.add_flag("--history", args.history, "Include PSO best-cost histories in the JSON")->group("Output");
}

// The shared option sets (constants, log format, signal processing, methods), --threads first.
void addProcessingOptions(CLI::App& cmd, IdentifyArgs& args) {
  cmd.add_option("--threads", args.signals.threads,
                 "Threads processing a long record's blocks (0 = all cores); the results are the same bytes whatever the number")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group("Signal processing");
  addConstantsOptions(cmd, args.constants);
  addLogInputOptions(cmd, args.log);
  addSignalOptions(cmd, args.signals);
  addMethodOptions(cmd, args.methods_options);
  args.wide_box_option = cmd.get_option("--wide-box");
  args.wide_box_option->description(
      "Half-width of the PSO baseline's box in every parameter (default for identify: 10 x the largest |LS estimate| of "
      "the records, printed; a PSO result on its box's bound is not usable)");
  args.wide_box_option->default_str("10 x the largest |LS estimate|");
}

#ifdef EXOID_WITH_MUJOCO
// A robot model other than the APAL leg, and what only its path takes.
void addChainOptions(CLI::App& cmd, IdentifyArgs& args) {
  cmd.add_option("--model", args.model,
                 "The robot: apal (the built-in APAL leg, the default), leg3 (the built-in hip-knee-ankle leg) or its MJCF or\n"
                 "URDF file. The records then have q_<joint>, tau_<joint> for its joints; its base parameters are fitted")
      ->group("Input");
  cmd.add_option("--plot", args.plot,
                 "A figure of each joint's measured and predicted torque (a chain's LS estimate, the APAL leg's first\n"
                 "--method's) on the first --validate record (else the first --data record), and its data as <plot>_series.csv")
      ->group("Output");
  addChainSelectionOptions(cmd, args.selection);
  cmd.add_option("--armature", args.armature,
                 "Joints (comma-separated, or all) that get an armature parameter, Ia qdd on the joint's own diagonal (a geared\n"
                 "motor's reflected rotor inertia), where the model file gives none (a URDF never does); the APAL leg: knee\n"
                 "(= --knee-armature)")
      ->delimiter(',')->group("Identification");
  cmd.add_flag("--moving-base-parameters", args.moving_base_parameters,
               "Chain models, records on a moving base (IMU columns): fit the base parameters of a moving base, where a\n"
               "joint's rotor inertia separates from its link's through the base's pitch acceleration. Exact with an exact\n"
               "pitch acceleration; an IMU's noise biases the split (docs/findings.md), hence off by default: the still\n"
               "base's parameters, with the base-motion terms in every column")
      ->group("Identification");
  cmd.add_option("--consistency-draws", args.consistency_draws,
                 "Chain models: estimates drawn about the nearest physically consistent one (the consistency verdict): LS is\n"
                 "inconsistent when p = (those as far from their own nearest consistent estimate + 1) / (draws + 1) is at most\n"
                 "the one-sided normal tail of --significance (2.3 % at 2); drawn only when LS is further than --significance\n"
                 "standard errors")
      ->check(CLI::Range(19, 1000000))->capture_default_str()->group("Identification");
  cmd.add_option("--consistency-seed", args.consistency_seed, "Chain models: the seed of the consistency verdict's draws")
      ->capture_default_str()->group("Identification");
  cmd.add_option("--stage", args.stages,
                 "The segmental strategy down the chain, distal joints first. JOINT=FILE: a record whose joints above JOINT\n"
                 "are locked (exoid simulate --lock); repeatable. Each stage fits what its moving joints' equations determine\n"
                 "that the more distal stages left open; --data, every joint moving, is the last stage. The APAL leg: knee=FILE\n"
                 "(= --knee-data FILE, --data as --both-data)")
      ->group("Input");
}
#endif

}  // namespace

void addIdentifyCommand(CLI::App& app) {
  auto args = std::make_shared<IdentifyArgs>();
  args->signals.threads = 0;  // a long record's blocks on every core (same bytes whatever the number)
  CLI::App* cmd = app.add_subcommand(
      "identify",
      "Identify X = [Mxt, Myt, Jt, fc1, fv1, Mxs, Mys, Js, fc2, fv2] from dataset CSV logs (.csv or\n"
      ".csv.gz; a lab's own columns and units through --profile or --columns).\n"
      "--data: all 10 parameters from both joint equations. --knee-data and --both-data: the paper's\n"
      "segmental strategy. Each is repeatable: the records of a role are processed one by one and\n"
      "fitted together. Exit code 3 when a result must not be used, naming why (outputs are still\n"
      "written): a parameter the record cannot identify (rank), a regressor whose condition number\n"
      "(columns scaled) exceeds --max-condition, a physically implausible estimate (Js <= 0, Jt <= Js,\n"
      "negative friction), or a PSO / RLS-PSO estimate on its search box's bound.");
  addInputOptions(*cmd, *args);
  addIdentificationOptions(*cmd, *args);
  addOutputOptions(*cmd, *args);
  addProcessingOptions(*cmd, *args);
#ifdef EXOID_WITH_MUJOCO
  addChainOptions(*cmd, *args);
#endif
  args->cmd = cmd;
  cmd->callback([args] { run(*args); });
}

}  // namespace exoid::experiments
