#include "exoid/experiments/sweep_job.hpp"

#include "exoid/ident/identifiability.hpp"
#include "exoid/ident/segmental.hpp"
#include "exoid/ident/stopwatch.hpp"
#include "exoid/experiments/sim_bridge.hpp"

#include <cstdio>
#include <regex>

namespace exoid::experiments {

namespace {

std::vector<double> vec(const Eigen::Ref<const Eigen::VectorXd>& x) { return {x.data(), x.data() + x.size()}; }

nlohmann::json errorStats(const ident::TorqueErrorStats& s) {
  return {{"mean_abs", s.mean_abs}, {"std_abs", s.std_abs}, {"rms", s.rms}};
}

}  // namespace

Eigen::VectorXd cramerRaoStd(const ProtocolResult& r, double sigma_Nm) {
  const ident::LegConstants lc{r.truths.lt_m, r.truths.g_mps2};
  Eigen::VectorXd crb(ident::kNumParams);
  const ident::SegmentalProblem knee = ident::kneeStage(r.records[0].ideal, lc);
  const ident::SegmentalProblem hip = ident::hipStage(r.records[2].ideal, r.truths.best_fit.tail<5>(), lc);
  crb.tail<5>() = ident::analyzeIdentifiability(knee.H, knee.y, sigma_Nm).crb_std;
  crb.head<5>() = ident::analyzeIdentifiability(hip.H, hip.y, sigma_Nm).crb_std;
  return crb;
}

nlohmann::json runSweepJob(const SweepConfig& config, JobId id) {
  ident::Stopwatch clock;
  const SweepCondition cond = config.conditions().at(static_cast<std::size_t>(id.cell));
  const std::uint64_t seed = config.jobSeed(id.cell, id.replicate);
  nlohmann::json j{{"cell", id.cell}, {"replicate", id.replicate}, {"seed", seed}, {"condition", toJson(cond)}};
  try {
    const ProtocolResult r = runProtocol(config.protocolFor(cond, seed));
    j["status"] = "ok";
    j["message"] = "";
    j["truth"] = {{"rigid", vec(r.truths.rigid)}, {"best_fit", vec(r.truths.best_fit)}};
    j["crb_std"] = vec(cramerRaoStd(r, cond.torque_noise_Nm));
    for (const VariantScore& s : r.scores) {
      j["methods"].push_back({{"method", toString(s.variant)},
                              {"status", s.outcome.usable() ? "ok" : "unusable"},
                              {"message", s.outcome.usable() ? std::string() : s.outcome.problems()},
                              {"x", vec(s.outcome.x)},
                              {"knee_validation", errorStats(s.knee_validation)},
                              {"hip_validation", errorStats(s.hip_validation)},
                              {"wall_time_s", s.outcome.wallTime_s()}});
    }
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
