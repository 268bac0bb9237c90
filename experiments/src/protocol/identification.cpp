#include "exoid/experiments/protocol/identification.hpp"

#include "exoid/experiments/protocol/stages_check.hpp"

#include "exoid/ident/estimators/segmental_errors.hpp"
#include "exoid/ident/model/base_estimate.hpp"
#include "exoid/experiments/report/cells.hpp"
#include "exoid/experiments/report/table.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/leg/plausibility.hpp"

#include "exoid/experiments/version.hpp"
#include "exoid/core/atomic_file.hpp"
#include "exoid/ident/estimators/segmental.hpp"
#include "exoid/ident/estimators/standard_errors.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <stdexcept>

namespace exoid::experiments {

using ident::kNumParams;

bool MethodOutcome::usable() const {
  for (const Stage& s : stages) {
    if (!ident::usable(s.estimate.summary.status)) return false;
  }
  return !stages.empty();
}

std::string MethodOutcome::problems() const {
  std::string out;
  for (const Stage& s : stages) {
    if (!ident::usable(s.estimate.summary.status)) {
      out += (out.empty() ? "" : "; ") + s.name + " stage: " + ident::toString(s.estimate.summary.status) +
             ": " + s.estimate.summary.message;
    }
  }
  return out;
}

std::vector<Eigen::Index> boxBoundIndices(const ident::Estimate& e) {
  std::vector<Eigen::Index> out;
  if ((e.method != ident::Method::kPso && e.method != ident::Method::kRlsPso) || !e.box) return out;
  const ident::Box& b = *e.box;
  for (Eigen::Index k = 0; k < e.x.size(); ++k) {
    const double v = e.x[k], tol = 1e-9 * (b.upper[k] - b.lower[k]);
    if (v <= b.lower[k] + tol || v >= b.upper[k] - tol) out.push_back(k);
  }
  return out;
}

std::string boxBoundMessage(const std::string& name, const ident::Estimate& e, Eigen::Index i) {
  return name + " = " + core::formatNumber(e.x[i], 6) + " is on its box's bound [" + core::formatNumber(e.box->lower[i], 6) + ", " +
         core::formatNumber(e.box->upper[i], 6) + "]";
}

std::vector<BoundHit> boxBoundHits(const MethodOutcome& m) {
  std::vector<BoundHit> hits;
  if (m.method != ident::Method::kPso && m.method != ident::Method::kRlsPso) return hits;
  for (const Stage& st : m.stages) {
    for (Eigen::Index k : boxBoundIndices(st.estimate)) {
      hits.push_back({st.name, st.indices[static_cast<std::size_t>(k)], st.estimate.x[k], st.estimate.box->lower[k], st.estimate.box->upper[k]});
    }
  }
  return hits;
}

std::string describe(const BoundHit& h) {
  return std::string(ident::paramName(h.param)) + " = " + core::formatNumber(h.value, 6) + " is on its box's bound [" +
         core::formatNumber(h.lower, 6) + ", " + core::formatNumber(h.upper, 6) + "]";
}

double MethodOutcome::wallTime_s() const {
  double t = 0.0;
  for (const Stage& s : stages) t += s.estimate.summary.wall_time_s;
  return t;
}

namespace {
std::vector<int> range(int first, int count) {
  std::vector<int> v(static_cast<std::size_t>(count));
  std::iota(v.begin(), v.end(), first);
  return v;
}

// Rank-deficiency messages name columns of the stage's problem; name the parameters instead.
void nameColumns(Stage& s) {
  auto& e = s.estimate;
  if (e.unidentifiable.empty()) return;
  std::string names;
  for (Eigen::Index c : e.unidentifiable) {
    names += (names.empty() ? "" : ", ") +
             std::string(ident::paramName(s.indices[static_cast<std::size_t>(c)]));
  }
  e.summary.message += " (not identifiable from this record: " + names + ")";
}
}  // namespace

namespace {
// Checks x against the physical conditions, leaving out what the stages could not identify.
void checkPlausibility(MethodOutcome& out) {
  std::vector<int> not_estimated;
  for (const Stage& st : out.stages) {
    for (Eigen::Index c : st.estimate.unidentifiable) not_estimated.push_back(st.indices[static_cast<std::size_t>(c)]);
  }
  out.implausible = ident::implausibilities(out.x, not_estimated);
  if (out.knee_armature && !(*out.knee_armature >= 0.0)) {
    out.implausible.push_back("Ia2 = " + core::toText(*out.knee_armature) + " kg m^2 must be >= 0 (an inertia)");
  }
}
}  // namespace

namespace {
// The outcome of one estimate of all parameters (10, or 11 with the knee armature last).
MethodOutcome allOutcome(ident::Method m, ident::Estimate e, bool knee_armature) {
  MethodOutcome out;
  out.method = m;
  Stage st{"all", range(0, kNumParams + (knee_armature ? 1 : 0)), std::move(e)};
  nameColumns(st);
  out.x = st.estimate.x.head(kNumParams);
  if (knee_armature) out.knee_armature = st.estimate.x[ident::kKneeArmature];
  out.stages.push_back(std::move(st));
  checkPlausibility(out);
  return out;
}

// The outcome of the segmental strategy's stages, each named after its first moving joint.
MethodOutcome segmentalOutcome(const ident::Robot& robot, ident::Method m, const ident::SegmentalResult& r) {
  MethodOutcome out;
  out.method = m;
  out.x = r.theta.head<kNumParams>();
  for (const ident::StageResult& st : r.stages) {
    out.stages.push_back({robot.chain.joints[static_cast<std::size_t>(st.problem.first_joint)].name, st.problem.parameters, st.estimate});
  }
  for (Stage& st : out.stages) nameColumns(st);
  checkPlausibility(out);
  return out;
}
}  // namespace

MethodOutcome identifyAll(ident::Method m, const ident::RecordRows& r, const ident::MethodOptions& o) {
  // Every equation in time order (hip row, knee row per sample), so RLS sees the record in order.
  return allOutcome(m, ident::estimate(m, r.W, r.y, o), r.W.cols() > kNumParams);
}

MethodOutcome identifyAll(ident::Estimate e, bool knee_armature) {
  const ident::Method m = e.method;
  return allOutcome(m, std::move(e), knee_armature);
}

std::vector<std::string> ConsistencyStep::withinNoise() const {
  std::vector<std::string> out;
  for (const ident::ConsistencyCheck& k : fit.checks) {
    if (!k.violated() || k.significant(significance_sigmas)) continue;
    out.push_back(k.name + " (value " + core::formatNumber(k.value, 4) + ", " +
                  (std::isinf(k.standard_error) ? std::string("standard error unknown") : core::formatNumber(-k.t(), 3) + " standard errors outside") + ")");
  }
  return out;
}

const char* const kReportedErrorsAre =
    "per parameter the larger of: Newey-West from the fit's residuals (Bartlett weights, automatic lag), and the jackknife: "
    "over contiguous blocks of the records (10 in all, at least 2 per record; the fit repeated without each block), which "
    "sees model error as slow as the motion, and with 3 records or more over whole records, which sees a bias that differs "
    "between records";
const char* const kSegmentalErrorsAre =
    "the same rule stage by stage (ident/estimators/segmental_errors.hpp): each stage's Newey-West and jackknives over its "
    "records, with what the earlier stages' errors carry into it through the torque it subtracts";

ident::ReportedErrors legReportedErrors(const ident::RecordRows& p, const Eigen::VectorXd& x) {
  // One channel, both equations of a sample one step (their residuals are correlated); the blocks
  // of the jackknife: each record cut into whole samples.
  return ident::reportedErrors(p.W, p.y, x, ident::interleavedChannels(p.W.rows(), 1), 2, ident::recordBlocks(p.record_rows, p.W.rows(), 2),
                               ident::wholeRecords(p.record_rows, p.W.rows()));
}

void applyConsistency(MethodOutcome& m, const ident::RecordRows& p, const ident::LegConstants& c,
                      const ident::ConsistencyOptions& options) {
  if (m.stages.size() != 1 || m.stages.front().name != "all") {
    throw std::invalid_argument("applyConsistency: needs a fit of all parameters at once (one stage 'all')");
  }
  const bool armature = m.knee_armature.has_value();
  const Eigen::VectorXd x = m.stages.front().estimate.x;
  // Rank, conditioning: reported as not usable already; the plain plausibility rule stays.
  if (!ident::usable(m.stages.front().estimate.summary.status)) return;
  ConsistencyStep step;
  step.unconstrained = x;
  step.significance_sigmas = options.significance_sigmas;
  step.errors = legReportedErrors(p, x);
  step.std_err = step.errors.reported;
  step.fit = ident::solveConsistentLeastSquares(p.W, p.y, c.thigh_length_m, x, step.errors.covariance, options);
  m.x = step.fit.x.head(kNumParams);
  if (armature) m.knee_armature = step.fit.x[ident::kKneeArmature];
  m.implausible = step.significant();
  m.consistency = std::move(step);
}

void applySegmentalConsistency(MethodOutcome& m, const ident::LegConstants& c, const ident::ConsistencyOptions& options) {
  if (!m.segmental_errors || m.knee_armature || m.segmental_errors->covariance.rows() != kNumParams) {
    throw std::invalid_argument("applySegmentalConsistency: needs a segmental LS outcome of the 10 parameters with its reported errors");
  }
  const Eigen::MatrixXd& C = m.segmental_errors->covariance;
  const Eigen::LLT<Eigen::MatrixXd> llt(C);
  if (!C.allFinite() || llt.info() != Eigen::Success) return;
  // C = L L', so (x' - x)' C^-1 (x' - x) = ||L^-1 (x' - x)||^2: least squares with H = L^-1, y = H x.
  const Eigen::MatrixXd H = llt.matrixL().solve(Eigen::MatrixXd::Identity(kNumParams, kNumParams));
  const Eigen::VectorXd x = m.x;
  ConsistencyStep step;
  step.unconstrained = x;
  step.significance_sigmas = options.significance_sigmas;
  step.errors = *m.segmental_errors;
  step.std_err = step.errors.reported;
  try {
    step.fit = ident::solveConsistentLeastSquares(H, H * x, c.thigh_length_m, x, C, options);
  } catch (const std::invalid_argument&) {
    return;  // C too ill-conditioned for the solver's rank rule: the plain plausibility rule stands
  }
  m.x = step.fit.x;
  m.implausible = step.significant();
  m.consistency = std::move(step);
}

MethodOutcome identifySegmented(const ident::Robot& robot, ident::Method m, const ident::RecordRows& knee_record,
                                const ident::RecordRows& both_record, const ident::MethodOptions& o) {
  const std::vector<ident::SegmentalStage> stages = {{1, knee_record}, {0, both_record}};
  const ident::SegmentalResult r = ident::identifySegmental(robot, stages, m, o);
  MethodOutcome out = segmentalOutcome(robot, m, r);
  if (m == ident::Method::kLs && r.usable()) out.segmental_errors = ident::segmentalReportedErrors(robot, stages, r);
  return out;
}

MethodOutcome identifySegmentedIdimIv(const ident::Robot& robot, const ident::ClosedLoopRecord& knee_record,
                                      const ident::ClosedLoopRecord& both_record, const ident::IvOptions& options) {
  return segmentalOutcome(robot, ident::Method::kIdimIv, ident::identifySegmentalIdimIv(robot, {{1, knee_record}, {0, both_record}}, options));
}

MethodOutcome identifyAllIdimIv(const ident::Robot& robot, const ident::ClosedLoopRecord& record, const ident::IvOptions& options) {
  return allOutcome(ident::Method::kIdimIv, ident::identifyIdimIv(robot, {record}, options), robot.knee_armature);
}

std::vector<ident::TorqueErrorStats> jointTorqueErrors(const ident::RecordRows& r, const Eigen::VectorXd& theta) {
  std::vector<ident::TorqueErrorStats> out;
  if (theta.size() != r.W.cols()) {
    throw std::invalid_argument("joint torque errors: " + core::toText(theta.size()) + " parameters for rows of " + core::toText(r.W.cols()));
  }
  for (Eigen::Index j = 0; j < r.dof; ++j) out.push_back(ident::torqueError(r.jointY(j), r.jointW(j) * theta));
  return out;
}

Validation validate(const ident::RecordRows& r, const ident::ParamVector& x, double knee_armature) {
  Eigen::VectorXd theta = Eigen::VectorXd::Zero(r.W.cols());
  theta.head<kNumParams>() = x;
  if (theta.size() > kNumParams) theta[ident::kKneeArmature] = knee_armature;  // the rows of a leg with the knee's armature
  const std::vector<ident::TorqueErrorStats> e = jointTorqueErrors(r, theta);
  return {e[0], e[1]};
}

nlohmann::json paramsJson(const Eigen::VectorXd& values, const std::vector<int>& indices) {
  nlohmann::json j = nlohmann::json::object();
  for (std::size_t k = 0; k < indices.size(); ++k) {
    j[std::string(ident::paramName(indices[k]))] = values[static_cast<Eigen::Index>(k)];
  }
  return j;
}

nlohmann::json paramsJson(const ident::ParamVector& x) { return paramsJson(x, range(0, kNumParams)); }

ident::ParamVector paramsFromJson(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object()) throw std::invalid_argument(where + ": expected an object of the 10 parameters by name");
  ident::ParamVector x;
  for (int i = 0; i < kNumParams; ++i) {
    const std::string name(ident::paramName(i));
    if (!j.contains(name)) throw std::invalid_argument(where + ": missing parameter '" + name + "'");
    if (!j[name].is_number()) throw std::invalid_argument(where + "." + name + ": expected a number");
    x[i] = j[name].get<double>();
  }
  for (const auto& [key, value] : j.items()) {
    if (ident::paramIndex(key) < 0) {
      throw std::invalid_argument(where + ": unknown parameter '" + key + "' (expected Mxt, Myt, Jt, fc1, fv1, Mxs, Mys, Js, fc2, fv2)");
    }
  }
  return x;
}

nlohmann::json toJson(const ident::TorqueErrorStats& s) {
  return {{"mean_abs_Nm", s.mean_abs}, {"std_abs_Nm", s.std_abs}, {"rms_Nm", s.rms}, {"max_abs_Nm", s.max_abs}};
}

nlohmann::json toJson(const Validation& v) { return {{"hip", toJson(v.hip)}, {"knee", toJson(v.knee)}}; }

nlohmann::json toJson(const ident::ParamError& e) {
  const auto all = range(0, static_cast<int>(e.abs.size()));
  return {{"abs", paramsJson(e.abs, all)}, {"rel", paramsJson(e.rel, all)}, {"norm_rel", e.norm_rel},
          {"max_abs_rel", e.max_abs_rel}};
}

nlohmann::json estimateJson(const ident::Estimate& e, bool with_history) {
  nlohmann::json j = {{"status", ident::toString(e.summary.status)},
                      {"message", e.summary.message},
                      {"iterations", e.summary.iterations},
                      {"l1_cost", e.l1_cost},
                      {"wall_time_s", e.summary.wall_time_s}};
  if (e.rank) j["rank"] = *e.rank;
  if (e.condition_number) j["condition_number"] = *e.condition_number;
  if (e.optimum_l1_cost) {
    j["optimum_l1_cost"] = *e.optimum_l1_cost;
    j["optimality_gap_rel"] = *e.optimality_gap_rel;
  }
  if (e.optimum_box_l1_cost) {
    j["optimum_box_l1_cost"] = *e.optimum_box_l1_cost;
    j["optimality_gap_box_rel"] = *e.optimality_gap_box_rel;
  }
  if (e.method == ident::Method::kIdimIv) {
    // IDIM-IV's history is its steps, in standard errors of each parameter (largest over them).
    j["iv_steps_in_standard_errors"] = e.cost_history;
  } else if (!e.cost_history.empty()) {
    j["initial_cost"] = e.summary.initial_cost;
    if (with_history) j["best_cost_history"] = e.cost_history;
  }
  return j;
}

nlohmann::json toJson(const Stage& s, bool with_history) {
  const ident::Estimate& e = s.estimate;
  nlohmann::json j = estimateJson(e, with_history);
  j["stage"] = s.name;
  j["parameters"] = paramsJson(e.x, s.indices);
  if (!e.unidentifiable.empty()) {
    nlohmann::json names = nlohmann::json::array();
    for (Eigen::Index c : e.unidentifiable) names.push_back(ident::paramName(s.indices[static_cast<std::size_t>(c)]));
    j["unidentifiable"] = names;
  }
  if (e.box) j["box"] = {{"lower", paramsJson(e.box->lower, s.indices)}, {"upper", paramsJson(e.box->upper, s.indices)}};
  return j;
}

nlohmann::json errorsJson(const ident::ReportedErrors& e, const char* are) {
  nlohmann::json se = nlohmann::json::object(), nw = nlohmann::json::object(), jk = nlohmann::json::object(), rj = nlohmann::json::object(),
                 from = nlohmann::json::object();
  for (Eigen::Index i = 0; i < e.reported.size(); ++i) {
    const std::string name(ident::paramName(static_cast<int>(i)));
    se[name] = jsonNumber(e.reported[i]);
    nw[name] = jsonNumber(e.newey_west[i]);
    jk[name] = jsonNumber(e.jackknife[i]);
    rj[name] = jsonNumber(e.record_jackknife[i]);
    from[name] = e.from_jackknife[static_cast<std::size_t>(i)] ? "jackknife" : "newey_west";
  }
  return {{"standard_errors", se},          {"standard_errors_newey_west", nw}, {"standard_errors_jackknife", jk},
          {"standard_errors_record_jackknife", rj}, {"standard_errors_from", from}, {"standard_errors_are", are}};
}

nlohmann::json toJson(const MethodOutcome& m, bool with_history) {
  nlohmann::json stages = nlohmann::json::array();
  for (const Stage& s : m.stages) stages.push_back(toJson(s, with_history));
  nlohmann::json j = {{"method", ident::toString(m.method)},
                      {"parameters", paramsJson(m.x)},
                      {"usable", m.usable()},
                      {"physically_plausible", m.implausible.empty()},
                      {"implausible", m.implausible},
                      {"wall_time_s", m.wallTime_s()},
                      {"stages", stages}};
  if (m.knee_armature) j["knee_armature"] = {{"Ia2", *m.knee_armature}, {"unit", "kg m^2"}};
  if (m.segmental_errors) j["segmental_errors"] = errorsJson(*m.segmental_errors, kSegmentalErrorsAre);
  if (m.consistency) {
    const ConsistencyStep& cs = *m.consistency;
    nlohmann::json checks = nlohmann::json::array();
    for (const ident::ConsistencyCheck& k : cs.fit.checks) {
      checks.push_back({{"condition", k.name}, {"value", k.value},
                        {"standard_error", jsonNumber(k.standard_error)},
                        {"violated", k.violated()}, {"significant", k.significant(cs.significance_sigmas)}, {"active", k.active}});
    }
    nlohmann::json un = nlohmann::json::object();
    for (Eigen::Index i = 0; i < cs.unconstrained.size(); ++i) un[std::string(ident::paramName(static_cast<int>(i)))] = cs.unconstrained[i];
    j["consistency"] = errorsJson(cs.errors, m.segmental_errors ? kSegmentalErrorsAre : kReportedErrorsAre);
    j["consistency"].update({{"constrained", cs.fit.constrained}, {"significance_sigmas", cs.significance_sigmas},
                             {"unconstrained_parameters", un}, {"checks", checks}});
  }
  return j;
}

std::map<std::string, ident::ParamVector> readTruthFile(const std::string& path) {
  const nlohmann::json j = readUserJsonFile(path, "truth file");
  std::map<std::string, ident::ParamVector> out;
  if (j.contains("parameters")) {
    out["truth"] = paramsFromJson(j["parameters"], path + ": parameters");
  } else if (j.contains("truth") && j["truth"].is_object()) {
    for (const auto& [name, t] : j["truth"].items()) {
      if (t.is_object() && t.contains("parameters")) {
        out[name] = paramsFromJson(t["parameters"], path + ": truth." + name + ".parameters");
      }
    }
  }
  if (out.empty()) {
    throw std::invalid_argument(path + ": expected {\"parameters\": {...}} or {\"truth\": {\"<name>\": {\"parameters\": {...}}}}");
  }
  return out;
}

nlohmann::json toolJson() { return {{"name", "exoid"}, {"version", kVersion}, {"revision", kGitRevision}}; }

void writeJsonFile(const std::string& path, const nlohmann::json& j) {
  core::writeFileAtomically(path, [&](std::ostream& out) { out << j.dump(2) << '\n'; });
}

nlohmann::json withoutWallTimes(nlohmann::json j) {
  if (j.is_object()) {
    j.erase("wall_time_s");
    for (auto& [k, v] : j.items()) v = withoutWallTimes(v);
  } else if (j.is_array()) {
    for (auto& v : j) v = withoutWallTimes(v);
  }
  return j;
}

nlohmann::json readUserJsonFile(const std::string& path, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(path + ": cannot open the " + what);
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(path + ": not valid JSON: " + e.what());
  }
}

nlohmann::json readJsonFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error("cannot parse " + path + ": " + e.what());
  }
}

nlohmann::json determinationJson(const ident::Robot& robot, const ident::Determination& d, const std::vector<std::string>& files) {
  if (files.size() != d.records.size()) {
    throw std::logic_error("determinationJson: " + std::to_string(files.size()) + " files for " + std::to_string(d.records.size()) + " records");
  }
  const auto signals = [](const std::vector<ident::SignalMotion>& list) {
    nlohmann::json out = nlohmann::json::array();
    for (const ident::SignalMotion& m : list) {
      out.push_back({{"name", m.name}, {"range", m.range}, {"noise", m.noise}, {"floor", m.floor}, {"moved", m.moved()}});
    }
    return out;
  };
  nlohmann::json records = nlohmann::json::array();
  for (std::size_t k = 0; k < d.records.size(); ++k) {
    const ident::RecordMotion& r = d.records[k];
    records.push_back({{"file", files[k]}, {"joints_rad", signals(r.joints)}, {"base_imu", signals(r.base)}, {"base_moved", r.baseMoved()}});
  }
  std::vector<std::string> names;
  for (int i : d.undetermined) names.push_back(robot.names()[static_cast<std::size_t>(i)]);
  return {{"records", records}, {"not_determined", names}};
}

std::string undeterminedProblem(const ident::Robot& robot, const ident::Determination& d) {
  if (d.undetermined.empty()) return "";
  return "not determined by the records' motion: " + d.describe(robot) +
         "; fit them from a record that moves their joints, or leave them to another stage";
}

std::string ArmatureTest::hint() const {
  if (joints.empty()) return "";
  return "the records show a joint armature the model leaves out (" + core::joined(shown, ", ") + "): rerun with " +
         (two_link ? "--knee-armature" : "--armature " + core::joined(joints, ","));
}

ArmatureTest armatureTest(const ident::Robot& with, const std::vector<ident::RecordRows>& rows, const std::vector<std::string>& joints,
                          double significance_sigmas, double max_condition) {
  ident::ChainEstimateOptions eo;
  eo.ls.max_condition = max_condition;
  eo.consistent = false;
  const ident::ChainEstimate e =
      ident::estimateChain(with, ident::stackRecords(rows), Eigen::VectorXd::Zero(with.chain.standardParameterCount()), eo);
  ArmatureTest t;
  t.two_link = with.two_link.has_value();
  if (t.two_link && joints != std::vector<std::string>{"knee"}) throw std::invalid_argument("armatureTest: the 2-link leg's armature is the knee's (Ia2)");
  if (e.ls.rank < with.parameters()) return t;
  // Each joint's armature by its name; one regrouped into a link's inertia is not a term of its own.
  std::vector<std::pair<std::string, Eigen::Index>> tested;
  for (const std::string& joint : joints) {
    const std::string name = t.two_link ? std::string(ident::paramName(ident::kKneeArmature)) : joint + ".Ia";
    const auto it = std::find(with.names().begin(), with.names().end(), name);
    if (it != with.names().end()) tested.emplace_back(joint, it - with.names().begin());
  }
  // One test per joint: Bonferroni keeps the chance that any of them fires on a rig without
  // armatures to --significance's one-sided tail.
  const double z = bonferroniZ(significance_sigmas, static_cast<int>(tested.size()));
  for (const auto& [joint, i] : tested) {
    const std::string name = with.names()[static_cast<std::size_t>(i)];
    const double value = e.beta[i], se = e.std_error[i];
    const bool significant = se > 0.0 && value > z * se;
    t.json[joint] = {{"value_kgm2", value}, {"std_error_kgm2", se}, {"significant", significant}, {"threshold_sigmas", z}};
    if (!significant) continue;
    t.joints.push_back(joint);
    t.shown.push_back(name + " = " + fmt(value, 4) + " +- " + fmt(se, 2) + " kg m^2, " + fmt(value / se, 3) + " standard errors above 0");
  }
  return t;
}

}  // namespace exoid::experiments
