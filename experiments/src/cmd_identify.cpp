// `exoid identify`: identify the 10 parameters from CSV logs with one or more methods.
#include "exoid/experiments/commands.hpp"
#include "exoid/experiments/controller_io.hpp"
#include "exoid/experiments/identification.hpp"
#include "exoid/experiments/options.hpp"
#include "exoid/experiments/table.hpp"
#include "exoid/ident/dataset.hpp"
#include "exoid/ident/preprocess.hpp"

#include <algorithm>
#include <iostream>
#include <memory>

namespace exoid::experiments {

namespace {

struct IdentifyArgs {
  std::string data, knee_data, both_data, json_out;
  std::vector<std::string> methods{"ls"};
  std::vector<std::string> validate;
  std::string truth;
  ConstantsFlags constants;
  ident::SignalOptions signals = defaultIdentifySignals();
  ident::MethodOptions methods_options;
  ident::IvOptions iv;
  std::string controller;  ///< JSON of the rig's controller (IDIM-IV); default: the records' metadata
  bool knee_armature = false;  ///< estimate Ia2 too
  bool history = false;
};

// What IDIM-IV needs of a record besides its rows: the reference and the controller it tracked.
ident::ClosedLoopRecord closedLoop(const IdentifyArgs& a, const std::string& file, const ident::Dataset& d,
                                   const ident::ProcessedRecord& rows, bool knee_only_record) {
  ident::ClosedLoopRecord r;
  r.measured = rows;
  r.controller = a.controller.empty() ? controllerFromMetadata(d, file) : readControllerJson(a.controller);
  r.reference = referenceOf(d, file);
  if (knee_only_record) r.controller.locked = {true, false};  // the segmental strategy's knee record: hip fixed
  return r;
}

std::vector<ident::Method> resolveMethods(const std::vector<std::string>& names) {
  std::vector<ident::Method> out;
  for (const std::string& n : names) {
    if (n == "all") {
      for (ident::Method m : ident::allMethods()) out.push_back(m);
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

void printResults(const std::vector<MethodOutcome>& outcomes,
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
  t.addRow(time);
  t.print(std::cout);
  if (!truths.empty()) std::cout << "(percent: relative error against '" << truths.begin()->first << "')\n";
  for (const MethodOutcome& m : outcomes) {
    for (const Stage& st : m.stages) {
      const auto& e = st.estimate;
      std::cout << ident::toString(m.method) << " [" << st.name << "]: " << e.summary.message;
      if (e.condition_number) std::cout << "; rank " << *e.rank << ", condition " << fmt(*e.condition_number, 4);
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

void run(const IdentifyArgs& a) {
  const bool single = !a.data.empty();
  const bool segmental = !a.knee_data.empty() || !a.both_data.empty();
  if (single == segmental) {
    throw CLI::ValidationError("identify", "give either --data FILE, or --knee-data FILE and --both-data FILE (segmental strategy)");
  }
  if (segmental && (a.knee_data.empty() || a.both_data.empty())) {
    throw CLI::ValidationError("identify", "the segmental strategy needs both --knee-data and --both-data");
  }
  if (segmental && a.knee_armature) {
    throw CLI::ValidationError("--knee-armature", "needs --data: a record where the hip moves, fitted with both equations (with "
                               "the hip fixed the armature's column is Js's, and Js enters the hip equation without it)");
  }
  const std::vector<ident::Method> methods = resolveMethods(a.methods);
  a.methods_options.validate();
  a.iv.validate();
  const bool iv = std::find(methods.begin(), methods.end(), ident::Method::kIdimIv) != methods.end();
  if (iv && a.signals.processing != ident::Processing::kParallel) {
    throw CLI::ValidationError("--method idim-iv", "needs '--processing parallel' (the default): its instruments are processed like the measured rows");
  }
  std::map<std::string, ident::ParamVector> truths;
  if (!a.truth.empty()) truths = readTruthFile(a.truth);

  const ident::Dataset primary = ident::readDatasetCsv(single ? a.data : a.both_data);
  std::string constants_origin;
  const ident::LegConstants c = resolveConstants(a.constants, primary, &constants_origin);
  const ident::ProcessedRecord r_primary = ident::processRecord(primary, c, a.signals);
  ident::ProcessedRecord r_knee;
  ident::Dataset knee_data;
  if (segmental) {
    knee_data = ident::readDatasetCsv(a.knee_data);
    r_knee = ident::processRecord(knee_data, c, a.signals);
  }
  // IDIM-IV's closed-loop descriptions, read before any work so a missing one fails fast.
  ident::ClosedLoopRecord cl_primary, cl_knee;
  if (iv) {
    cl_primary = closedLoop(a, single ? a.data : a.both_data, primary, r_primary, false);
    if (segmental) cl_knee = closedLoop(a, a.knee_data, knee_data, r_knee, true);
  }

  std::vector<MethodOutcome> outcomes;
  for (ident::Method m : methods) {
    if (m == ident::Method::kIdimIv) {
      outcomes.push_back(single ? identifyAllIdimIv(cl_primary, c, a.signals, a.iv, a.knee_armature)
                                : identifySegmentedIdimIv(cl_knee, cl_primary, c, a.signals, a.iv));
      continue;
    }
    outcomes.push_back(single ? identifyAll(m, r_primary, a.methods_options, a.knee_armature)
                              : identifySegmented(m, r_knee, r_primary, a.methods_options));
  }
  std::vector<std::pair<std::string, std::vector<Validation>>> validations;
  for (const std::string& file : a.validate) {
    const ident::ProcessedRecord rv = ident::processRecord(ident::readDatasetCsv(file), c, a.signals);
    std::vector<Validation> v;
    for (const MethodOutcome& m : outcomes) v.push_back(validate(rv, m.x, m.knee_armature.value_or(0.0)));
    validations.emplace_back(file, std::move(v));
  }

  printResults(outcomes, validations, truths);

  if (!a.json_out.empty()) {
    nlohmann::json j;
    j["tool"] = toolJson();
    j["command"] = "identify";
    j["strategy"] = single ? "all_parameters_one_record" : "segmental";
    j["inputs"] = single ? nlohmann::json{{"data", a.data}}
                         : nlohmann::json{{"knee_data", a.knee_data}, {"both_data", a.both_data}};
    // Whether the base-motion terms were in the rows (base_terms auto uses them when present).
    j["base_terms_used"] = a.signals.processing == ident::Processing::kParallel &&
                           (a.signals.base_terms == ident::BaseTerms::kOn ||
                            (a.signals.base_terms == ident::BaseTerms::kAuto && ident::hasBaseColumns(primary)));
    j["constants"] = {{"thigh_length_m", c.thigh_length_m}, {"gravity_mps2", c.gravity_mps2}, {"origin", constants_origin}};
    j["signal_options"] = toJson(a.signals);
    j["method_options"] = toJson(a.methods_options);
    j["seed"] = a.methods_options.rls_pso.pso.seed;
    j["methods"] = nlohmann::json::object();
    for (std::size_t k = 0; k < outcomes.size(); ++k) {
      nlohmann::json mj = toJson(outcomes[k], a.history);
      for (const auto& [file, vals] : validations) mj["validation"][file] = toJson(vals[k]);
      for (const auto& [name, x] : truths) mj["parameter_error"][name] = toJson(ident::paramError(outcomes[k].x, x));
      j["methods"][ident::toString(outcomes[k].method)] = mj;
    }
    // The first method's estimate at top level, for tools that expect one answer.
    j["method"] = ident::toString(outcomes.front().method);
    j["parameters"] = paramsJson(outcomes.front().x);
    j["status"] = outcomes.front().usable() && outcomes.front().implausible.empty() ? "usable" : "not_usable";
    if (!truths.empty()) {
      j["truth"] = nlohmann::json::object();
      for (const auto& [name, x] : truths) j["truth"][name] = paramsJson(x);
    }
    writeJsonFile(a.json_out, j);
  }
  std::string problems;
  for (const MethodOutcome& m : outcomes) {
    if (!m.usable()) problems += (problems.empty() ? "" : "; ") + std::string(ident::toString(m.method)) + ": " + m.problems();
    for (const std::string& v : m.implausible) {
      problems += (problems.empty() ? "" : "; ") + std::string(ident::toString(m.method)) + ": physically implausible: " + v;
    }
  }
  if (!problems.empty()) throw UnusableResult(problems);
}

}  // namespace

void addIdentifyCommand(CLI::App& app) {
  auto args = std::make_shared<IdentifyArgs>();
  CLI::App* cmd = app.add_subcommand(
      "identify",
      "Identify X = [Mxt, Myt, Jt, fc1, fv1, Mxs, Mys, Js, fc2, fv2] from dataset CSV logs.\n"
      "One record (--data): all 10 parameters from both joint equations. Two records\n"
      "(--knee-data, --both-data): the paper's segmental strategy. Exit code 3 when a result\n"
      "must not be used (e.g. the record cannot identify a parameter); outputs are still written.");
  cmd->add_option("--data", args->data, "Dataset CSV: identify all 10 parameters from both equations")
      ->check(CLI::ExistingFile)->group("Input");
  cmd->add_option("--knee-data", args->knee_data, "Segmental step 1: knee-only record (hip fixed)")
      ->check(CLI::ExistingFile)->group("Input");
  cmd->add_option("--both-data", args->both_data, "Segmental step 2: record where both joints swing")
      ->check(CLI::ExistingFile)->group("Input");
  cmd->add_option("--method", args->methods,
                  "ls, rls, pso, rls-pso, lad, idim-iv, or all (= all but idim-iv) (repeatable). idim-iv needs the\n"
                  "records' q_hip_ref, q_knee_ref columns and their controller (--controller, or the\n"
                  "'# controller_*' metadata exoid simulate writes)")
      ->capture_default_str()->delimiter(',')->group("Input");
  cmd->add_option("--controller", args->controller,
                  "IDIM-IV: JSON of the rig's controller {\"kp\": [hip, knee], \"kd\": [..], \"ki\": [..],\n"
                  "\"derivative_cutoff_hz\": .., \"integral_limit_Nm\": .., \"feedforward\": \"model\"|\"none\",\n"
                  "\"hip_locked\": false}; default: the records' metadata")
      ->check(CLI::ExistingFile)->group("Input");
  cmd->add_flag("--knee-armature", args->knee_armature,
               "Also estimate Ia2, the knee's armature (reflected rotor/actuator inertia on its own diagonal, kg m^2): "
               "Ia2 qdd2 joins the knee equation only; needs --data (both equations of a record where the hip moves)")
      ->group("Identification");
  cmd->add_option("--iv-tolerance", args->iv.step_tolerance, "IDIM-IV: stop when every step < this many standard errors, (0, 1)")
      ->capture_default_str()->group("Identification");
  cmd->add_option("--iv-max-iterations", args->iv.max_iterations, "IDIM-IV: iteration limit, >= 1")
      ->capture_default_str()->group("Identification");
  cmd->add_option("--validate", args->validate, "Validation record(s): torque error per joint (repeatable)")
      ->check(CLI::ExistingFile)->group("Input");
  cmd->add_option("--truth", args->truth, "Truth JSON ({\"parameters\": {...}} or a simulation sidecar): parameter errors")
      ->check(CLI::ExistingFile)->group("Input");
  cmd->add_option("--json", args->json_out, "Write the results as JSON here (atomically)")->group("Output");
  cmd->add_flag("--history", args->history, "Include PSO best-cost histories in the JSON")->group("Output");
  addConstantsOptions(*cmd, args->constants);
  addSignalOptions(*cmd, args->signals);
  addMethodOptions(*cmd, args->methods_options);
  cmd->callback([args] { run(*args); });
}

}  // namespace exoid::experiments
