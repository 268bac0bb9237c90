#include "exoid/experiments/sweep/sweep_job.hpp"

#include "exoid/experiments/sweep/robot_sweep.hpp"

#include "exoid/ident/design/identifiability.hpp"
#include "exoid/ident/estimators/segmental.hpp"
#include "exoid/ident/estimators/stopwatch.hpp"
#include "exoid/experiments/protocol/sim_bridge.hpp"

#include <cstdio>
#include <regex>

namespace exoid::experiments {

namespace {

std::vector<double> vec(const Eigen::Ref<const Eigen::VectorXd>& x) { return {x.data(), x.data() + x.size()}; }

nlohmann::json errorStats(const ident::TorqueErrorStats& s) {
  return {{"mean_abs", s.mean_abs}, {"std_abs", s.std_abs}, {"rms", s.rms}};
}

// Per stage: gap against the unconstrained and the box-constrained L1 optimum (PSO, RLS-PSO).
nlohmann::json gapsJson(const MethodOutcome& m) {
  nlohmann::json g = nlohmann::json::object();
  for (const Stage& st : m.stages) {
    if (st.estimate.optimality_gap_rel) g[st.name]["unconstrained"] = *st.estimate.optimality_gap_rel;
    if (st.estimate.optimality_gap_box_rel) g[st.name]["box"] = *st.estimate.optimality_gap_box_rel;
  }
  return g;
}

// The APAL leg's run: the protocol's truths and its scores per method.
nlohmann::json apalSweepRun(const SweepConfig& config, const SweepCondition& cond, std::uint64_t seed) {
  const ProtocolResult r = runProtocol(config.protocolFor(cond, seed));
  nlohmann::json j{{"truth", {{"rigid", vec(r.truths.rigid)}, {"best_fit", vec(r.truths.best_fit)}}}, {"methods", nlohmann::json::array()}};
  for (const VariantScore& s : r.scores) {
    j["methods"].push_back({{"method", toString(s.variant)},
                            {"status", s.outcome.usable() ? "ok" : "unusable"},
                            {"message", s.outcome.usable() ? std::string() : s.outcome.problems()},
                            {"x", vec(s.outcome.x)},
                            {"crb_std", vec(s.crb_std)},
                            {"implausible", s.outcome.implausible},
                            {"torque_space", {{"best_fit", {{"hip", s.torque_space_vs_best_fit.hip}, {"knee", s.torque_space_vs_best_fit.knee}}},
                                              {"rigid", {{"hip", s.torque_space_vs_rigid.hip}, {"knee", s.torque_space_vs_rigid.knee}}}}},
                            {"optimality_gaps", gapsJson(s.outcome)},
                            {"knee_validation", errorStats(s.knee_validation)},
                            {"hip_validation", errorStats(s.hip_validation)},
                            {"wall_time_s", s.outcome.wallTime_s()}});
    if (s.outcome.segmental_errors) j["methods"].back()["std_error"] = vec(s.outcome.segmental_errors->reported);
  }
  return j;
}

}  // namespace

nlohmann::json runSweepJob(const SweepConfig& config, JobId id) {
  ident::Stopwatch clock;
  const SweepCondition cond = config.conditions().at(static_cast<std::size_t>(id.cell));
  const std::uint64_t seed = config.jobSeed(id.cell, id.replicate);
  nlohmann::json j{{"cell", id.cell}, {"replicate", id.replicate}, {"seed", seed}, {"condition", toJson(cond)}};
  try {
    j.update(config.isChain() ? runChainSweepRun(config, cond, seed) : apalSweepRun(config, cond, seed));
    j["status"] = "ok";
    j["message"] = "";
  } catch (const std::exception& e) {
    j["status"] = "error";
    j["message"] = e.what();
    j["methods"] = nlohmann::json::array();
  }
  j["wall_time_s"] = clock.seconds();
  return j;
}

std::string jobFileName(JobId id) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "job-%05d-%04d.json", id.cell, id.replicate);
  return buf;
}

std::optional<JobId> parseJobFileName(const std::string& name) {
  static const std::regex kPattern(R"(job-(\d{5,})-(\d{4,})\.json)");
  std::smatch m;
  if (!std::regex_match(name, m, kPattern)) return std::nullopt;
  return JobId{std::stoi(m[1].str()), std::stoi(m[2].str())};
}

}  // namespace exoid::experiments
