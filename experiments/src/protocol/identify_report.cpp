#include "exoid/experiments/protocol/identify_report.hpp"

#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/protocol/options.hpp"

namespace exoid::experiments {

nlohmann::json toJson(const IdentifyEnvelope& e) {
  nlohmann::json j;
  j["tool"] = toolJson();
  j["command"] = "identify";
  j["strategy"] = e.stages.empty() ? "all_parameters_one_record" : "segmental";
  j["model"] = e.model;
  j["inputs"] = {{"data", e.data}, {"validate", e.validate}, {"sampling", e.sampling}};
  j["inputs"]["stages"] = nlohmann::json::array();
  for (const auto& [joint, file] : e.stages) j["inputs"]["stages"].push_back({{"joint", joint}, {"file", file}});
  if (!e.profile.empty()) j["inputs"]["profile"] = e.profile;
  j["signal_options"] = toJson(e.signals);
  j["method_options"] = toJson(e.methods);
  j["seed"] = e.methods.rls_pso.pso.seed;
  j["problems"] = e.problems;
  j["status"] = e.problems.empty() ? "usable" : "not_usable";
  return j;
}

}  // namespace exoid::experiments
