#include "exoid/experiments/protocol/controller_io.hpp"
#include "exoid/experiments/protocol/identification.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace exoid::experiments {

namespace {

double parseNumber(const std::string& text, const std::string& where) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size()) throw std::invalid_argument(where + ": expected a number, got '" + text + "'");
  return v;
}

std::string required(const ident::Dataset& d, const std::string& key, const std::string& source) {
  const auto v = d.metadata(key);
  if (!v) {
    throw std::invalid_argument(source + ": no '# " + key + ": ...' metadata line; IDIM-IV needs the controller the log "
                                "was recorded under (give --controller FILE.json for a real rig)");
  }
  return *v;
}

Eigen::Vector2d pairOf(const std::string& text, const std::string& where) {
  const auto comma = text.find(',');
  if (comma == std::string::npos) throw std::invalid_argument(where + ": expected 'hip,knee', got '" + text + "'");
  return {parseNumber(text.substr(0, comma), where), parseNumber(text.substr(comma + 1), where)};
}

bool boolOf(const std::string& text, const std::string& where) {
  if (text == "true") return true;
  if (text == "false") return false;
  throw std::invalid_argument(where + ": expected true or false, got '" + text + "'");
}

// A controller file's JSON object; throws naming the file when it cannot be read or is not one.
nlohmann::json readControllerObject(const std::string& path) {
  nlohmann::json j = readUserJsonFile(path, "controller file");
  if (!j.is_object()) throw std::invalid_argument(path + ": expected a JSON object");
  return j;
}

// A controller file's "feedforward": "model" or "none" (absent: none).
ident::Feedforward feedforwardOf(const nlohmann::json& j, const std::string& path) {
  if (!j.contains("feedforward")) return ident::Feedforward::kNone;
  if (!j["feedforward"].is_string()) throw std::invalid_argument(path + ": 'feedforward' must be \"model\" or \"none\"");
  try {
    return ident::parseFeedforward(j["feedforward"].get<std::string>());
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": 'feedforward': " + e.what());
  }
}

}  // namespace

ident::ControllerModel controllerFromMetadata(const ident::Dataset& d, const std::string& source) {
  ident::ControllerModel c;
  const auto key = [&](const std::string& k) { return required(d, k, source); };
  const auto where = [&](const std::string& k) { return source + ": metadata '" + k + "'"; };
  c.pid.kp_Nm_per_rad = pairOf(key("controller_kp_Nm_per_rad"), where("controller_kp_Nm_per_rad"));
  c.pid.ki_Nm_per_rad_s = pairOf(key("controller_ki_Nm_per_rad_s"), where("controller_ki_Nm_per_rad_s"));
  c.pid.kd_Nms_per_rad = pairOf(key("controller_kd_Nms_per_rad"), where("controller_kd_Nms_per_rad"));
  c.pid.derivative_cutoff_hz = parseNumber(key("controller_derivative_cutoff_Hz"), where("controller_derivative_cutoff_Hz"));
  c.pid.integral_limit_Nm = parseNumber(key("controller_integral_limit_Nm"), where("controller_integral_limit_Nm"));
  c.feedforward = boolOf(key("feedforward"), where("feedforward")) ? ident::Feedforward::kModel : ident::Feedforward::kNone;
  c.locked = {boolOf(key("hip_locked"), where("hip_locked")), false};
  try {
    c.validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(source + ": " + e.what());
  }
  return c;
}

ident::ControllerModel readControllerJson(const std::string& path) {
  const nlohmann::json j = readControllerObject(path);
  static const char* const known[] = {"kp", "ki", "kd", "derivative_cutoff_hz", "integral_limit_Nm", "feedforward", "hip_locked"};
  for (const auto& [k, v] : j.items()) {
    bool ok = false;
    for (const char* name : known) ok = ok || k == name;
    if (!ok) throw std::invalid_argument(path + ": unknown field '" + k + "' (expected kp, ki, kd, derivative_cutoff_hz, integral_limit_Nm, feedforward, hip_locked)");
  }
  const auto pair = [&](const char* name, bool needed) -> Eigen::Vector2d {
    if (!j.contains(name)) {
      if (needed) throw std::invalid_argument(path + ": missing '" + name + "' ([hip, knee])");
      return Eigen::Vector2d::Zero();
    }
    const auto& v = j[name];
    if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number()) {
      throw std::invalid_argument(path + ": '" + name + "' must be [hip, knee] numbers");
    }
    return {v[0].get<double>(), v[1].get<double>()};
  };
  ident::ControllerModel c;
  c.pid.kp_Nm_per_rad = pair("kp", true);
  c.pid.ki_Nm_per_rad_s = pair("ki", false);
  c.pid.kd_Nms_per_rad = pair("kd", true);
  const auto number = [&](const char* name, double fallback) {
    if (!j.contains(name)) return fallback;
    if (!j[name].is_number()) throw std::invalid_argument(path + ": '" + name + "' must be a number");
    return j[name].get<double>();
  };
  c.pid.derivative_cutoff_hz = number("derivative_cutoff_hz", 0.0);
  c.pid.integral_limit_Nm = number("integral_limit_Nm", 1e300);
  c.feedforward = feedforwardOf(j, path);
  if (j.contains("hip_locked")) {
    if (!j["hip_locked"].is_boolean()) throw std::invalid_argument(path + ": 'hip_locked' must be true or false");
    c.locked = {j["hip_locked"].get<bool>(), false};
  }
  try {
    c.validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": " + e.what());
  }
  return c;
}

ident::Reference referenceOf(const ident::Dataset& d, const std::string& source) {
  Eigen::MatrixX2d q(d.size(), 2);
  for (int j = 0; j < 2; ++j) {
    const std::string name = j == 0 ? "q_hip_ref" : "q_knee_ref";
    bool found = false;
    for (const auto& n : d.extra_names) found = found || n == name;
    if (!found) {
      throw std::invalid_argument(source + ": no '" + name + "' column; IDIM-IV simulates the controller tracking "
                                  "its reference and needs q_hip_ref and q_knee_ref (rad)");
    }
    q.col(j) = d.extraColumn(name);
  }
  return ident::Reference::fromAngles(d.t_s, q);
}

ident::ClosedLoopRecord closedLoopRecord(const ident::Dataset& d, const std::string& source,
                                         const ident::ProcessedRecord& rows, const std::string& controller_json,
                                         bool knee_only_record) {
  ident::ClosedLoopRecord r;
  r.measured = rows;
  r.controller = controller_json.empty() ? controllerFromMetadata(d, source) : readControllerJson(controller_json);
  r.reference = referenceOf(d, source);
  if (knee_only_record) r.controller.locked = {true, false};
  return r;
}

namespace {

Eigen::VectorXd listOf(const std::string& text, const std::string& where) {
  std::vector<double> v;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = text.find(',', start);
    v.push_back(parseNumber(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start), where));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

}  // namespace

ident::ChainController chainControllerFromMetadata(const ident::Dataset& d, const std::string& source) {
  if (const auto locked = d.metadata("locked_joints"); locked && !locked->empty()) {
    throw std::invalid_argument(source + ": joints " + *locked + " are locked in this record (metadata 'locked_joints'); IDIM-IV "
                                "simulates the closed loop of every joint: give it records in which every joint moves");
  }
  ident::ChainController c;
  const auto key = [&](const std::string& k) { return required(d, k, source); };
  const auto where = [&](const std::string& k) { return source + ": metadata '" + k + "'"; };
  c.kp_Nm_per_rad = listOf(key("controller_kp_Nm_per_rad"), where("controller_kp_Nm_per_rad"));
  c.kd_Nms_per_rad = listOf(key("controller_kd_Nms_per_rad"), where("controller_kd_Nms_per_rad"));
  c.feedforward = boolOf(key("feedforward"), where("feedforward")) ? ident::Feedforward::kModel : ident::Feedforward::kNone;
  if (const auto bw = d.metadata("actuator_bandwidth_Hz")) c.actuator_bandwidth_hz = parseNumber(*bw, where("actuator_bandwidth_Hz"));
  try {
    c.validate(static_cast<int>(d.dof()));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(source + ": " + e.what());
  }
  return c;
}

ident::ChainController readChainControllerJson(const std::string& path, int dof) {
  const nlohmann::json j = readControllerObject(path);
  for (const auto& [k, v] : j.items()) {
    if (k != "kp" && k != "kd" && k != "feedforward" && k != "actuator_bandwidth_hz") {
      throw std::invalid_argument(path + ": unknown field '" + k + "' (a chain's controller: kp, kd, feedforward, actuator_bandwidth_hz)");
    }
  }
  const auto gains = [&](const char* name) {
    if (!j.contains(name)) throw std::invalid_argument(path + ": missing '" + name + "' (one number per joint, " + std::to_string(dof) + ")");
    const auto& v = j[name];
    if (!v.is_array() || static_cast<int>(v.size()) != dof) {
      throw std::invalid_argument(path + ": '" + name + "' must be an array of " + std::to_string(dof) + " numbers (one per joint)");
    }
    Eigen::VectorXd g(dof);
    for (int i = 0; i < dof; ++i) {
      if (!v[static_cast<std::size_t>(i)].is_number()) throw std::invalid_argument(path + ": '" + name + "' must hold numbers");
      g[i] = v[static_cast<std::size_t>(i)].get<double>();
    }
    return g;
  };
  ident::ChainController c;
  c.kp_Nm_per_rad = gains("kp");
  c.kd_Nms_per_rad = gains("kd");
  c.feedforward = feedforwardOf(j, path);
  if (j.contains("actuator_bandwidth_hz")) {
    if (!j["actuator_bandwidth_hz"].is_number()) throw std::invalid_argument(path + ": 'actuator_bandwidth_hz' must be a number");
    c.actuator_bandwidth_hz = j["actuator_bandwidth_hz"].get<double>();
  }
  try {
    c.validate(dof);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": " + e.what());
  }
  return c;
}

ident::ChainReference chainReferenceOf(const ident::Dataset& d, const std::string& source) {
  Eigen::MatrixXd q(d.size(), d.dof());
  for (Eigen::Index j = 0; j < d.dof(); ++j) {
    const std::string name = "q_" + d.joints[static_cast<std::size_t>(j)] + "_ref";
    if (std::find(d.extra_names.begin(), d.extra_names.end(), name) == d.extra_names.end()) {
      throw std::invalid_argument(source + ": no '" + name + "' column; IDIM-IV simulates the controller tracking its reference and "
                                  "needs q_<joint>_ref (rad) for every joint");
    }
    q.col(j) = d.extraColumn(name);
  }
  try {
    return ident::ChainReference::fromAngles(d.t_s, q);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(source + ": the q_<joint>_ref columns: " + e.what());
  }
}

}  // namespace exoid::experiments
