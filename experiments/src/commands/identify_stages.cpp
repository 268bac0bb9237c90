// `exoid identify --model M --stage JOINT=FILE ... --data FILE`: the segmental strategy down a
// chain (ident/estimators/segmental.hpp), every method stage by stage.
#include "exoid/core/format.hpp"
#include "exoid/experiments/commands/robot_commands.hpp"
#include "exoid/experiments/commands/commands.hpp"
#include "exoid/experiments/protocol/band_sensitivity.hpp"
#include "exoid/experiments/protocol/excitation_report.hpp"
#include "exoid/experiments/protocol/fit_records.hpp"
#include "exoid/experiments/protocol/robot_loader.hpp"
#include "exoid/experiments/protocol/stages_check.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/report/table.hpp"
#include "exoid/ident/estimators/segmental.hpp"
#include "exoid/ident/estimators/segmental_errors.hpp"
#include "exoid/ident/model/base_estimate.hpp"
#include "exoid/ident/model/consistent_fit.hpp"
#include "exoid/ident/model/determination.hpp"
#include "exoid/ident/signals/processing.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <numeric>
#include <optional>

namespace exoid::experiments {

std::vector<ChainStageInput> stageInputs(const ChainIdentifyArgs& a, const ident::ChainModel& model) {
  const std::vector<std::string> names = model.jointNames();
  std::map<Eigen::Index, std::vector<std::string>, std::greater<>> by_joint;
  for (const auto& [joint, file] : a.stages) {
    const auto it = std::find(names.begin(), names.end(), joint);
    if (it == names.end()) {
      const std::string all = core::joined(names);
      throw std::invalid_argument("--stage " + joint + "=" + file + ": '" + joint + "' is not a joint of the model (" + all + ")");
    }
    const auto j = static_cast<Eigen::Index>(it - names.begin());
    if (j == 0) {
      throw std::invalid_argument("--stage " + joint + "=" + file + ": with every joint moving the record is the last stage's: give it with --data");
    }
    by_joint[j].push_back(file);
  }
  std::vector<ChainStageInput> out;
  for (const auto& [j, files] : by_joint) out.push_back({j, files});
  out.push_back({0, a.data});
  return out;
}

namespace {

std::string lockedJoints(const ident::ChainModel& model, Eigen::Index first) {
  std::string s;
  for (Eigen::Index j = 0; j < first; ++j) s += (s.empty() ? "" : ", ") + model.joints[static_cast<std::size_t>(j)].name;
  return s;
}

// Each stage's records, processed with the stage's joints above its first moving one locked.
struct StageRecords {
  std::vector<ident::SegmentalStage> stages;
  nlohmann::json json = nlohmann::json::array();
  /// The last stage's (every joint moving) first record: its processing, for the validation
  /// records, and its rows, for --plot without them.
  ident::SignalOptions fit_signals;
  std::optional<ident::RecordRows> shown;
  /// Each stage's records' processing as used, and the band chosen from each (the band sensitivity).
  std::vector<std::vector<ident::SignalOptions>> signals;
  std::vector<std::vector<std::optional<ident::BandChoice>>> bands;
};

StageRecords readStages(const ChainIdentifyArgs& a, const LoadedChain& loaded, const std::vector<ChainStageInput>& inputs,
                        const std::vector<std::vector<ident::Dataset>>& data) {
  const ident::ChainModel& model = loaded.model;
  StageRecords out;
  for (std::size_t s = 0; s < inputs.size(); ++s) {
    const ChainStageInput& in = inputs[s];
    ident::BandRule rule;
    rule.first_moving_joint = in.first_joint;
    // The stage's records are stacked into one fit: one choice of the base-motion terms for them.
    FitRecords fit = processFitRecords(in.files, data[s], loaded.robot, a.signals, rule);
    if (s + 1 == inputs.size()) {
      // The last stage's first record: the validation records' processing, and --plot's rows without them.
      out.fit_signals = fit.validationSignals(a.signals);
      if (!a.plot.empty() && a.validate.empty()) out.shown = fit.rows.front();
    }
    out.signals.push_back(std::move(fit.signals));
    out.bands.push_back(std::move(fit.bands));
    out.stages.push_back({in.first_joint, ident::stackRecords(fit.rows)});
    out.json.push_back({{"first_joint", model.joints[static_cast<std::size_t>(in.first_joint)].name},
                        {"locked", lockedJoints(model, in.first_joint)},
                        {"processing_per_record", fit.json}});
  }
  return out;
}

// LS first, then the other methods.
std::vector<ident::Method> stageMethods(const ChainIdentifyArgs& a) {
  std::vector<ident::Method> methods = {ident::Method::kLs};
  for (ident::Method m : a.methods) {
    if (m != ident::Method::kLs) methods.push_back(m);
  }
  return methods;
}

// Every method down the stages, in `methods`' order, with `mo` as they ran.
std::vector<ident::SegmentalResult> identifyStages(const ChainIdentifyArgs& a, const LoadedChain& loaded,
                                                        const std::vector<ident::SegmentalStage>& stages,
                                                        const std::vector<ident::Method>& methods, ident::MethodOptions& mo) {
  mo = a.method_options;
  mo.ls.max_condition = a.max_condition;
  std::vector<ident::SegmentalResult> results;
  for (ident::Method m : methods) {
    results.push_back(ident::identifySegmental(loaded.robot, stages, m, mo));
    if (m == ident::Method::kLs && !a.wide_box_given) mo.wide_box_half_width = ident::psoHalfWidthFromLs(results.front().theta);
  }
  return results;
}

// Stage s: what it identifies and each method's result there (printed, into its JSON `sj`), and
// why a method's result there must not be used (appended to `problems`).
void reportStage(std::size_t s, const ident::ChainModel& model, const std::vector<ident::Method>& methods,
                 const std::vector<ident::SegmentalResult>& results, bool with_history, nlohmann::json& sj, std::vector<std::string>& problems) {
  const ident::StageProblem& st = results.front().stages[s].problem;
  const std::string joint = model.joints[static_cast<std::size_t>(st.first_joint)].name;
  std::cout << "stage " << s + 1 << ": " << (st.first_joint == 0 ? "every joint moves" : "joints from " + joint + " down move, " +
                                                                                             lockedJoints(model, st.first_joint) + " locked")
            << "; " << st.rows.size() << " equations; identifies " << st.directions.cols() << ":";
  for (const std::string& n : st.names) std::cout << " " << n << ";";
  std::cout << "\n";
  // How well the stage's records excite what it identifies (LS's factor), as one fit reports its records'.
  std::cout << wrapped(describe(excitationOf(results.front().stages[s].estimate, st.names), "the stage's records",
                                       "a record moving these joints differently would separate them"))
            << "\n";
  for (std::size_t k = 0; k < methods.size(); ++k) {
    const ident::Estimate& e = results[k].stages[s].estimate;
    std::cout << "  " << ident::toString(methods[k]) << ": " << e.summary.message;
    if (e.condition_number) std::cout << ", condition number " << fmt(*e.condition_number, 4);
    std::cout << "\n";
    if (!ident::usable(e.summary.status)) {
      problems.push_back("stage " + core::toText(s + 1) + ", " + ident::toString(methods[k]) + ": " + e.summary.message);
    }
    for (Eigen::Index i : boxBoundIndices(e)) {
      problems.push_back("stage " + core::toText(s + 1) + ", " + ident::toString(methods[k]) + ": " +
                         boxBoundMessage(st.names[static_cast<std::size_t>(i)], e, i));
    }
  }
  sj["equations"] = st.rows.size();
  sj["identifies"] = st.names;
  for (std::size_t k = 0; k < methods.size(); ++k) {
    const ident::Estimate& e = results[k].stages[s].estimate;
    nlohmann::json& mj = sj["methods"][ident::toString(methods[k])] = estimateJson(e, with_history);
    mj["values"] = toVector(e.x);
  }
}

// The stage (1-based; 0: none) after which each base parameter is determined: it then lies in
// the span of the combinations identified so far (the directions are orthonormal, across stages too).
std::vector<int> knownAfterStage(const ident::SegmentalResult& ls, int rank) {
  std::vector<int> stage_of(static_cast<std::size_t>(rank), 0);
  Eigen::VectorXd known_share = Eigen::VectorXd::Zero(rank);
  for (std::size_t s = 0; s < ls.stages.size(); ++s) {
    const ident::StageProblem& st = ls.stages[s].problem;
    for (Eigen::Index i = 0; i < rank; ++i) {
      known_share[i] += st.directions.row(i).squaredNorm();
      if (known_share[i] > 1.0 - 1e-9 && stage_of[static_cast<std::size_t>(i)] == 0) stage_of[static_cast<std::size_t>(i)] = static_cast<int>(s + 1);
    }
  }
  return stage_of;
}

// LS's standard errors (std err) beside its estimate when every LS stage is usable.
void printStageEstimates(const ident::BaseParameters& base, const std::vector<ident::Method>& methods,
                         const std::vector<ident::SegmentalResult>& results, const std::vector<int>& stage_of,
                         const std::optional<Eigen::VectorXd>& truth, const std::optional<ident::ReportedErrors>& errors) {
  std::vector<std::string> header = {"base parameter", "known after stage"};
  for (ident::Method m : methods) header.push_back(ident::toString(m));
  if (errors) header.insert(header.begin() + 3, "std err");
  if (truth) header.insert(header.end(), {"truth", "ls err %"});
  if (truth && errors) header.push_back("err / std");
  TextTable table(header);
  for (int i = 0; i < base.rank; ++i) {
    std::vector<std::string> row = {base.names[static_cast<std::size_t>(i)], core::toText(stage_of[static_cast<std::size_t>(i)])};
    for (const ident::SegmentalResult& r : results) row.push_back(fmt(r.theta[i], 6));
    if (errors) row.insert(row.begin() + 3, fmt(errors->reported[i], 3));
    if (truth) {
      const double ls = results.front().theta[i];
      row.push_back(fmt((*truth)[i], 6));
      row.push_back(std::abs((*truth)[i]) > 0.0 ? fmt(100.0 * (ls - (*truth)[i]) / std::abs((*truth)[i]), 3) : "-");
      if (errors) row.push_back(errors->reported[i] > 0.0 ? fmt((ls - (*truth)[i]) / errors->reported[i], 3) : "-");
    }
    table.addRow(row);
  }
  table.print(std::cout);
  printCombinations(std::cout, base.names, base.combinations);
  if (errors) {
    std::cout << wrapped("std err: LS's standard errors, the larger of Newey-West and a jackknife over blocks of the records, stage by "
                         "stage with what the earlier stages' errors carry into each later one")
              << "\n";
  }
}

// How much LS down the stages depends on the bands chosen from the records: every chosen cutoff a
// quarter wider (whole records), the stages refitted, the change in LS's reported errors (as one
// fit's band sensitivity). None when no band was chosen or the refit is not usable.
std::optional<BandSensitivity> stagesBandSensitivity(const ChainIdentifyArgs& a, const LoadedChain& loaded, const StageRecords& records,
                                                     const std::vector<std::vector<ident::Dataset>>& data, const ident::MethodOptions& mo,
                                                     const Eigen::VectorXd& theta, const Eigen::VectorXd& std_err) {
  bool chosen = false;
  for (const auto& stage : records.bands) chosen = chosen || std::any_of(stage.begin(), stage.end(), [](const auto& b) { return b.has_value(); });
  if (!chosen) return std::nullopt;
  BandRefit refit;
  std::vector<ident::SegmentalStage> wider;
  for (std::size_t s = 0; s < data.size(); ++s) {
    std::vector<ident::RecordRows> rows;
    for (std::size_t r = 0; r < data[s].size(); ++r) {
      const ident::SignalOptions o = widerBand(records.signals[s][r], records.bands[s][r], a.signals.derivative_cutoff_from_data,
                                               1.0 / data[s][r].sampleInterval_s(), refit.factor);
      rows.push_back(ident::processRecord(data[s][r], loaded.robot, o));
    }
    wider.push_back({records.stages[s].first_joint, ident::stackRecords(rows)});
  }
  ident::MethodOptions any_condition = mo;  // a refit is compared, not judged (as one fit's)
  any_condition.ls.max_condition = std::numeric_limits<double>::max();
  const ident::SegmentalResult ls = ident::identifySegmental(loaded.robot, wider, ident::Method::kLs, any_condition);
  if (!ls.usable()) return std::nullopt;
  refit.wider = ls.theta;
  return bandSensitivity(refit, loaded.robot, theta, std_err);
}

// The stages' own JSON: LS's reported errors, the consistent estimate, the other methods.
nlohmann::json stagesJson(const nlohmann::json& stages_json, const std::vector<ident::Method>& methods,
                          const std::vector<ident::SegmentalResult>& results, const std::optional<ident::ReportedErrors>& errors,
                          const std::optional<NearestConsistent>& consistent, std::uint64_t seed) {
  nlohmann::json j;
  j["stages"] = stages_json;
  j["base_parameters"] = nlohmann::json::object();
  if (errors) j["base_parameters"].update(baseErrorsJson(errors->reported, *errors, kSegmentalErrorsAre));
  j["methods"] = nlohmann::json::object();
  for (std::size_t k = 1; k < methods.size(); ++k) {
    j["methods"][ident::toString(methods[k])] = {{"beta", toVector(results[k].theta)}, {"usable", results[k].usable()}};
  }
  if (consistent) {
    j["base_parameters"]["consistent"] = toVector(consistent->fit.beta);
    j["consistent"] = {{"status", ident::toString(consistent->fit.status)}, {"standard_errors_from_ls", consistent->verdict.distance},
                       {"verdict", toJson(consistent->verdict, seed)}, {"metric", "LS's reported covariance"}};
  }
  return j;
}

// The stages against one fit of the last stage's records (stages_check.hpp), when those records
// alone determine every base parameter and the model does not explain them to rounding (exact
// data leave no term out; their errors are rounding too).
struct OneFitCheck {
  nlohmann::json json;
  std::string problem;  ///< empty: the one fit is consistent, or it could not be judged
};

OneFitCheck againstOneFit(const ChainIdentifyArgs& a, const LoadedChain& loaded, const LogInput& log, const ChainStageInput& last_input,
                          const StageRecords& records, const Eigen::VectorXd& theta, const Eigen::VectorXd& std_error) {
  OneFitCheck out;
  ident::ChainEstimateOptions eo;
  eo.ls.max_condition = a.max_condition;
  eo.consistent = a.consistency;
  const ident::RecordRows& last = records.stages.back().record;
  const ident::ChainEstimate one = ident::estimateChain(loaded.robot, last, loaded.phi, eo);
  std::string why;
  if (one.ls.rank < loaded.base.rank || one.ls.summary.status == ident::Status::kIllConditioned || !one.std_error.allFinite()) {
    why = "those records alone do not determine every base parameter";
  } else if (!std_error.allFinite() || !theta.allFinite()) {
    why = "the stages' estimate or errors are not finite";
  } else if (explainedToRounding(last.W, last.y, one.beta)) {
    why = "the model explains them to rounding: no term is left out";
  }
  if (!why.empty()) {
    out.json = notJudged(why);
    return out;
  }
  StagesAgainstOneFit c = compareStagesWithOneFit(theta, std_error, one.beta, one.std_error, a.significance_sigmas);
  c.consistency_judged = a.consistency;
  // Judged as its own identify would judge it, the optional-term test included.
  const LsConsistency consistency = a.consistency ? judgeLeastSquares(a, loaded, log, one, last_input.files, records.signals.back(), "them")
                                                  : LsConsistency{};
  if (!consistency.reason.empty()) {
    c.one_fit_inconsistency = consistency.verdict.significant ? "is not explained by the model: " + consistency.reason
                                                              : "shows a term by the armature test (" + consistency.reason + ")";
  }
  std::cout << wrapped(describe(c, loaded.base.names)) << "\n";
  out.json = toJson(c, loaded.base.names);
  if (consistency.verdict.distance > 0.0) out.json["verdict"] = toJson(consistency.verdict, a.consistency_seed);
  if (c.one_fit_inconsistency.empty()) return out;
  if (consistency.armature) out.json["armature"] = consistency.armature->json;
  out.problem = stagesHidProblem(c, consistency.hint);
  return out;
}

}  // namespace

ChainFit fitStages(const ChainIdentifyArgs& a, const LoadedChain& loaded, const LogInput& log, const std::vector<ChainStageInput>& inputs,
                   const std::vector<std::vector<ident::Dataset>>& data, const std::optional<Eigen::VectorXd>& truth) {
  StageRecords records = readStages(a, loaded, inputs, data);
  const std::vector<ident::Method> methods = stageMethods(a);
  ChainFit out;
  const std::vector<ident::SegmentalResult> results = identifyStages(a, loaded, records.stages, methods, out.method_options);
  // What each stage's own motion determines of what it fits (its combinations, over its moving
  // joints' equations), stage by stage as the fit runs.
  std::vector<ident::DeterminationStage> moving;
  for (std::size_t s = 0; s < data.size(); ++s) {
    std::vector<Eigen::Index> equations(static_cast<std::size_t>(loaded.model.dof() - records.stages[s].first_joint));
    std::iota(equations.begin(), equations.end(), records.stages[s].first_joint);
    moving.push_back({&data[s], &records.stages[s].record, equations, results.front().stages[s].problem.directions});
  }
  const ident::Determination determination = ident::determination(loaded.robot, moving);
  if (const std::string p = undeterminedProblem(loaded.robot, determination); !p.empty()) {
    std::cout << p << '\n';
    out.problems.push_back(p);
  }
  for (std::size_t s = 0; s < results.front().stages.size(); ++s) reportStage(s, loaded.model, methods, results, a.history, records.json[s], out.problems);
  std::optional<ident::ReportedErrors> errors;
  if (results.front().usable()) errors = ident::segmentalReportedErrors(loaded.robot, records.stages, results.front());
  printStageEstimates(loaded.base, methods, results, knownAfterStage(results.front(), loaded.base.rank), truth, errors);
  // LS's physically consistent estimate: the stages share no rows, so the nearest in the metric of
  // LS's reported covariance (one fit uses its rows' metric).
  std::optional<NearestConsistent> consistent;
  if (a.consistency && errors) consistent = nearestConsistent(loaded, results.front().theta, errors->covariance, "LS", verdictOptions(a));
  if (consistent) {
    const ident::ConsistencyVerdict& v = consistent->verdict;
    std::cout << wrapped("consistent estimate (the nearest in LS's reported errors): " + std::string(ident::toString(consistent->fit.status)) + ", " +
                         fmt(v.distance, 3) + " reported standard errors from LS" + (v.distance > 0.0 ? ", " + verdictText(v) : std::string()))
              << "\n";
    if (v.significant) out.problems.push_back(inconsistencyProblem(v, "the data", "reported standard errors"));
  }
  std::optional<OneFitCheck> one_fit;
  if (errors) {
    one_fit = againstOneFit(a, loaded, log, inputs.back(), records, results.front().theta, errors->reported);
    if (!one_fit->problem.empty()) out.problems.push_back(one_fit->problem);
  }
  out.ls = results.front().theta;
  if (errors) out.std_error = errors->reported;
  for (std::size_t k = 1; k < methods.size(); ++k) out.others.emplace_back(ident::toString(methods[k]), results[k].theta);
  out.fit_signals = records.fit_signals;
  out.shown = std::move(records.shown);
  out.json = stagesJson(records.json, methods, results, errors, consistent, a.consistency_seed);
  std::vector<std::string> files;  // the records in the stages' order
  for (const ChainStageInput& in : inputs) files.insert(files.end(), in.files.begin(), in.files.end());
  out.json["determination"] = determinationJson(loaded.robot, determination, files);
  if (one_fit) out.json["against_one_fit"] = one_fit->json;
  if (errors) {
    if (const auto sensitivity = stagesBandSensitivity(a, loaded, records, data, out.method_options, out.ls, errors->reported)) {
      for (const std::string& line : describe(*sensitivity)) std::cout << wrapped(line) << "\n";
      out.json["band_sensitivity"] = toJson(*sensitivity);
    }
  }
  if (a.consistency && errors) judgeOthersConsistency(a, loaded, errors->covariance, out);
  return out;
}

}  // namespace exoid::experiments
