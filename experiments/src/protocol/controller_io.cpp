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

// The joints named in a list ("hip,knee" or a JSON array) as a lock mask; throws naming an unknown one.
std::vector<bool> lockMask(const std::vector<std::string>& names, const std::vector<std::string>& joints, const std::string& where) {
  std::vector<bool> locked(joints.size(), false);
  for (const std::string& n : names) {
    const auto it = std::find(joints.begin(), joints.end(), n);
    if (it == joints.end()) throw std::invalid_argument(where + ": '" + n + "' is not a joint of the record");
    locked[static_cast<std::size_t>(it - joints.begin())] = true;
  }
  return locked;
}

std::vector<std::string> splitNames(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = text.find(',', start);
    const std::string name = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (!name.empty()) out.push_back(name);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

ident::Controller validated(ident::Controller c, const std::vector<std::string>& joints, const std::string& source) {
  try {
    c.validate(joints);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(source + ": " + e.what());
  }
  return c;
}

}  // namespace

ident::Controller controllerFromMetadata(const ident::Dataset& d, const std::string& source) {
  ident::Controller c;
  const auto key = [&](const std::string& k) { return required(d, k, source); };
  const auto where = [&](const std::string& k) { return source + ": metadata '" + k + "'"; };
  const auto optional = [&](const std::string& k, double fallback) {
    const auto v = d.metadata(k);
    return v ? parseNumber(*v, where(k)) : fallback;
  };
  c.kp_Nm_per_rad = listOf(key("controller_kp_Nm_per_rad"), where("controller_kp_Nm_per_rad"));
  c.kd_Nms_per_rad = listOf(key("controller_kd_Nms_per_rad"), where("controller_kd_Nms_per_rad"));
  if (const auto ki = d.metadata("controller_ki_Nm_per_rad_s")) c.ki_Nm_per_rad_s = listOf(*ki, where("controller_ki_Nm_per_rad_s"));
  c.derivative_cutoff_hz = optional("controller_derivative_cutoff_Hz", 0.0);
  c.integral_limit_Nm = optional("controller_integral_limit_Nm", 1e300);
  c.actuator_bandwidth_hz = optional("actuator_bandwidth_Hz", 0.0);
  if (const auto law = d.metadata("controller_law"); law && (*law == "pd_measured_velocity" || *law == "pid_measured_velocity")) c.derivative = ident::DerivativeSource::kMeasuredVelocity;
  c.feedforward = boolOf(key("feedforward"), where("feedforward")) ? ident::Feedforward::kModel : ident::Feedforward::kNone;
  std::vector<std::string> locked;
  if (const auto hip = d.metadata("hip_locked"); hip && boolOf(*hip, where("hip_locked"))) locked.push_back("hip");
  if (const auto names = d.metadata("locked_joints")) {
    for (const std::string& n : splitNames(*names)) locked.push_back(n);
  }
  if (!locked.empty()) c.locked = lockMask(locked, d.joints, where(d.metadata("locked_joints") ? "locked_joints" : "hip_locked"));
  return validated(c, d.joints, source);
}

ident::Controller readControllerJson(const std::string& path, const std::vector<std::string>& joints) {
  const nlohmann::json j = readControllerObject(path);
  static const char* const known[] = {"kp",           "ki",          "kd",     "derivative", "derivative_cutoff_hz", "integral_limit_Nm",
                                      "feedforward", "actuator_bandwidth_hz", "locked", "hip_locked"};
  for (const auto& [k, v] : j.items()) {
    bool ok = false;
    for (const char* name : known) ok = ok || k == name;
    if (!ok) {
      throw std::invalid_argument(path + ": unknown field '" + k + "' (expected kp, ki, kd, derivative, derivative_cutoff_hz, "
                                  "integral_limit_Nm, feedforward, actuator_bandwidth_hz, locked, hip_locked)");
    }
  }
  const auto dof = joints.size();
  const auto gains = [&](const char* name, bool needed) -> Eigen::VectorXd {
    if (!j.contains(name)) {
      if (needed) throw std::invalid_argument(path + ": missing '" + name + "' (one number per joint, " + std::to_string(dof) + ")");
      return Eigen::VectorXd::Zero(static_cast<Eigen::Index>(dof));
    }
    const auto& v = j[name];
    if (!v.is_array() || v.size() != dof) {
      throw std::invalid_argument(path + ": '" + name + "' must be an array of " + std::to_string(dof) + " numbers (one per joint)");
    }
    Eigen::VectorXd g(static_cast<Eigen::Index>(dof));
    for (std::size_t i = 0; i < dof; ++i) {
      if (!v[i].is_number()) throw std::invalid_argument(path + ": '" + name + "' must hold numbers");
      g[static_cast<Eigen::Index>(i)] = v[i].get<double>();
    }
    return g;
  };
  const auto number = [&](const char* name, double fallback) {
    if (!j.contains(name)) return fallback;
    if (!j[name].is_number()) throw std::invalid_argument(path + ": '" + name + "' must be a number");
    return j[name].get<double>();
  };
  ident::Controller c;
  c.kp_Nm_per_rad = gains("kp", true);
  c.ki_Nm_per_rad_s = gains("ki", false);
  c.kd_Nms_per_rad = gains("kd", true);
  c.derivative_cutoff_hz = number("derivative_cutoff_hz", 0.0);
  c.integral_limit_Nm = number("integral_limit_Nm", 1e300);
  c.actuator_bandwidth_hz = number("actuator_bandwidth_hz", 0.0);
  c.feedforward = feedforwardOf(j, path);
  if (j.contains("derivative")) {
    const auto& v = j["derivative"];
    if (v == "measured_velocity") {
      c.derivative = ident::DerivativeSource::kMeasuredVelocity;
    } else if (v != "error_difference") {
      throw std::invalid_argument(path + ": 'derivative' must be \"error_difference\" or \"measured_velocity\"");
    }
  }
  std::vector<std::string> locked;
  if (j.contains("hip_locked")) {
    if (!j["hip_locked"].is_boolean()) throw std::invalid_argument(path + ": 'hip_locked' must be true or false");
    if (j["hip_locked"].get<bool>()) locked.push_back("hip");
  }
  if (j.contains("locked")) {
    if (!j["locked"].is_array()) throw std::invalid_argument(path + ": 'locked' must be an array of joint names");
    for (const auto& n : j["locked"]) {
      if (!n.is_string()) throw std::invalid_argument(path + ": 'locked' must be an array of joint names");
      locked.push_back(n.get<std::string>());
    }
  }
  if (!locked.empty()) c.locked = lockMask(locked, joints, path + ": 'locked'");
  return validated(c, joints, path);
}

ident::Reference referenceOf(const ident::Dataset& d, const std::string& source) {
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
    return ident::Reference::fromAngles(d.t_s, q);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(source + ": the q_<joint>_ref columns: " + e.what());
  }
}

ident::ClosedLoopRecord closedLoopRecord(const ident::Dataset& d, const std::string& source, const ident::RecordRows& rows,
                                         const ident::SignalOptions& signals, const std::string& controller_json,
                                         Eigen::Index locked_below) {
  ident::ClosedLoopRecord r;
  r.measured = rows;
  r.signals = signals;
  r.controller = controller_json.empty() ? controllerFromMetadata(d, source) : readControllerJson(controller_json, d.joints);
  r.reference = referenceOf(d, source);
  if (locked_below > 0) {
    r.controller.locked.assign(static_cast<std::size_t>(d.dof()), false);
    for (Eigen::Index j = 0; j < locked_below; ++j) r.controller.locked[static_cast<std::size_t>(j)] = true;
  }
  return r;
}

}  // namespace exoid::experiments
