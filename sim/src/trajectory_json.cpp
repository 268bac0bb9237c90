#include "exoid/sim/trajectory_json.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace exoid::sim {

namespace {
std::vector<double> column(const Eigen::MatrixXd& m, Eigen::Index j) {
  std::vector<double> v(static_cast<std::size_t>(m.rows()));
  for (Eigen::Index k = 0; k < m.rows(); ++k) v[static_cast<std::size_t>(k)] = m(k, j);
  return v;
}

// j[key], or an error naming where + key.
const nlohmann::json& need(const nlohmann::json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key)) throw std::invalid_argument(where + key + " is missing");
  return j[key];
}

double number(const nlohmann::json& j, const char* key, const std::string& where) {
  const nlohmann::json& v = need(j, key, where);
  if (!v.is_number()) throw std::invalid_argument(where + key + ": expected a number, got " + v.dump());
  return v.get<double>();
}

std::vector<double> numbers(const nlohmann::json& j, const char* key, const std::string& where) {
  const nlohmann::json& v = need(j, key, where);
  if (!v.is_array() || v.empty()) throw std::invalid_argument(where + key + ": expected a non-empty list of numbers");
  std::vector<double> out;
  for (const nlohmann::json& x : v) {
    if (!x.is_number()) throw std::invalid_argument(where + key + ": expected numbers, got " + x.dump());
    out.push_back(x.get<double>());
  }
  return out;
}
}  // namespace

nlohmann::json trajectoryJson(const core::FourierSeries& f, const std::vector<std::string>& joints) {
  if (static_cast<int>(joints.size()) != f.dof()) throw std::invalid_argument("trajectoryJson: one name per joint");
  nlohmann::json list = nlohmann::json::array();
  for (Eigen::Index k = 0; k < f.dof(); ++k) {
    list.push_back({{"name", joints[static_cast<std::size_t>(k)]},
                    {"offset_rad", f.offset_rad[k]},
                    {"cos_rad", column(f.a_rad, k)},
                    {"sin_rad", column(f.b_rad, k)}});
  }
  return {{"f0_hz", f.f0_hz}, {"locked_joints", f.locked_joints}, {"joints", list}};
}

NamedTrajectory trajectoryFromJson(const nlohmann::json& j) {
  const nlohmann::json& joints = need(j, "joints", "");
  if (!joints.is_array() || joints.empty()) throw std::invalid_argument("joints: expected a non-empty list of joints");
  const double locked = number(j, "locked_joints", "");
  if (!(locked >= 0 && locked <= static_cast<double>(joints.size()) && locked == std::floor(locked))) {
    throw std::invalid_argument("locked_joints: expected a whole number in [0, " + std::to_string(joints.size()) + "]");
  }
  const double f0_hz = number(j, "f0_hz", "");
  // Every joint read and its sizes checked before the series is allocated (joints x harmonics): a
  // file's size bounds what it costs.
  struct Joint {
    double offset;
    std::vector<double> cos, sin;
  };
  std::vector<Joint> read;
  NamedTrajectory out;
  for (std::size_t k = 0; k < joints.size(); ++k) {
    const std::string where = "joints[" + std::to_string(k) + "].";
    if (!joints[k].is_object()) throw std::invalid_argument("joints[" + std::to_string(k) + "]: expected an object (name, offset_rad, cos_rad, sin_rad)");
    const nlohmann::json& name = need(joints[k], "name", where);
    if (!name.is_string() || name.get<std::string>().empty()) throw std::invalid_argument(where + "name: expected a non-empty string");
    if (std::find(out.joints.begin(), out.joints.end(), name.get<std::string>()) != out.joints.end()) {
      throw std::invalid_argument(where + "name: '" + name.get<std::string>() + "' names two joints");
    }
    out.joints.push_back(name.get<std::string>());
    read.push_back({number(joints[k], "offset_rad", where), numbers(joints[k], "cos_rad", where), numbers(joints[k], "sin_rad", where)});
    for (const auto& [key, v] : {std::pair{"cos_rad", &read.back().cos}, std::pair{"sin_rad", &read.back().sin}}) {
      if (v->size() != read.front().cos.size()) {
        throw std::invalid_argument(where + key + ": " + std::to_string(v->size()) + " harmonics, joints[0] has " +
                                    std::to_string(read.front().cos.size()));
      }
    }
  }
  const auto harmonics = static_cast<Eigen::Index>(read.front().cos.size());
  out.series = core::FourierSeries::still(static_cast<int>(read.size()), static_cast<int>(harmonics), f0_hz);
  out.series.locked_joints = static_cast<int>(locked);
  for (std::size_t k = 0; k < read.size(); ++k) {
    const auto K = static_cast<Eigen::Index>(k);
    out.series.offset_rad[K] = read[k].offset;
    out.series.a_rad.col(K) = Eigen::Map<const Eigen::VectorXd>(read[k].cos.data(), harmonics);
    out.series.b_rad.col(K) = Eigen::Map<const Eigen::VectorXd>(read[k].sin.data(), harmonics);
  }
  try {
    out.series.validate();
  } catch (const std::invalid_argument& e) {  // its "trajectory: " is the caller's to say
    const std::string what = e.what(), prefix = "trajectory: ";
    throw std::invalid_argument(what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what);
  }
  return out;
}

}  // namespace exoid::sim
