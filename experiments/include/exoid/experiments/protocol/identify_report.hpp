#pragma once
// What identify's JSON holds around its estimates on every leg, in one form: the strategy, the
// robot, the records (the fit's, the stages', the validation's), the options as used, the seed,
// and why the result must not be used (the reasons of exit code 3) with the status they give.
#include "exoid/ident/estimators/methods.hpp"
#include "exoid/ident/signals/preprocess.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace exoid::experiments {

struct IdentifyEnvelope {
  /// {"name", "joints", ...}: a chain's model file, or the APAL leg's 2-link model of its constants.
  nlohmann::json model;
  std::vector<std::string> data;  ///< the fit's records (with stages: the last stage's, every joint moving)
  /// The segmental strategy's earlier stages as given: (first moving joint, record). Empty: one fit.
  std::vector<std::pair<std::string, std::string>> stages;
  std::vector<std::string> validate;
  nlohmann::json sampling = nlohmann::json::object();  ///< each record's sampling as read and used, by file
  std::string profile;                                 ///< the log profile, if any
  ident::SignalOptions signals;
  ident::MethodOptions methods;  ///< as the methods ran (the PSO box sized from the data)
  std::vector<std::string> problems;
};

/// {"tool", "command": "identify", "strategy": "all_parameters_one_record" | "segmental", "model",
/// "inputs": {"data", "stages": [{"joint", "file"}], "validate", "sampling", "profile"},
/// "signal_options", "method_options", "seed", "problems", "status": "usable" | "not_usable"}.
nlohmann::json toJson(const IdentifyEnvelope& e);

}  // namespace exoid::experiments
