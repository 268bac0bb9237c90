#include "exoid/experiments/protocol/excitation_io.hpp"
#include "exoid/core/format.hpp"
#include "exoid/experiments/protocol/identification.hpp"

#include <Eigen/Cholesky>

#include <cmath>
#include <stdexcept>

namespace exoid::experiments {

namespace {
// The five bounds of a trajectory (its limits, or what it reached), per joint.
template <class Bounds>
nlohmann::json boundsJson(const Bounds& b) {
  const auto list = [](const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); };
  return {{"q_min_rad", list(b.q_min_rad)},
          {"q_max_rad", list(b.q_max_rad)},
          {"qd_max_radps", list(b.qd_max_radps)},
          {"qdd_max_radps2", list(b.qdd_max_radps2)},
          {"tau_max_Nm", list(b.tau_max_Nm)}};
}
}  // namespace

nlohmann::json limitsJson(const ident::ExcitationLimits& limits, const std::string& source) {
  nlohmann::json j = boundsJson(limits);
  j["source"] = source;
  return j;
}

nlohmann::json scoreJson(const ident::ExcitationDesign& d) {
  // No wall time: same seed, same bytes.
  return {{"condition_number", d.score.condition_number}, {"sum_log_std", d.score.sum_log_std},
          {"worst_violation", d.score.worst_violation},   {"reached", boundsJson(d.score)},
          {"evaluations", d.evaluations},                 {"feasible_restarts", d.feasible_restarts}};
}

sim::NamedTrajectory readExcitationFile(const std::string& path, const std::vector<std::string>& joints) {
  const nlohmann::json j = readUserJsonFile(path, "excitation file");
  // Before a6738e0 an APAL design's trajectory had a_rad/b_rad per joint and a chain design its
  // joints at the top: said as such, not as a missing key.
  const bool older = j.is_object() && ((j.contains("trajectory") && j["trajectory"].is_object() && j["trajectory"].contains("a_rad")) ||
                                       (!j.contains("trajectory") && j.contains("joints")));
  if (older) {
    throw std::invalid_argument(path + ": a design in an older exoid's form (before a6738e0); design it again with exoid excite, or "
                                "move its coefficients to trajectory.joints[k] {name, offset_rad, cos_rad (a_rad), sin_rad (b_rad)}");
  }
  if (!j.is_object() || !j.contains("trajectory") || !j["trajectory"].is_object()) {
    throw std::invalid_argument(path + ": expected an object with a \"trajectory\" object (as exoid excite writes)");
  }
  sim::NamedTrajectory t;
  try {
    t = sim::trajectoryFromJson(j["trajectory"]);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": trajectory: " + e.what());
  }
  if (!joints.empty() && t.joints != joints) {
    throw std::invalid_argument(path + ": the design moves " + core::joined(t.joints) + "; this robot's joints are " +
                                core::joined(joints) + " (a design of another robot: exoid excite designs one for this robot)");
  }
  return t;
}

ident::ExcitationLimits paperEnvelope(const ident::LegConstants& c, const ident::ParamVector& nominal) {
  ident::ExcitationLimits wide;
  wide.q_min_rad = Eigen::Vector2d::Constant(-10.0);
  wide.q_max_rad = Eigen::Vector2d::Constant(10.0);
  wide.qd_max_radps = wide.qdd_max_radps2 = wide.tau_max_Nm = Eigen::Vector2d::Constant(1e9);
  ident::ExcitationLimits env;
  env.q_min_rad = Eigen::Vector2d::Constant(1e9);
  env.q_max_rad = Eigen::Vector2d::Constant(-1e9);
  env.qd_max_radps = env.qdd_max_radps2 = env.tau_max_Nm = Eigen::Vector2d::Zero();
  const ident::Robot leg = ident::twoLinkLeg(c);
  for (int id = 1; id <= 4; ++id) {
    const core::FourierSeries t = sim::paperTrajectory(id);
    const ident::ExcitationScore s = ident::scoreExcitation(leg, t, nominal, wide, 1000);
    env.q_min_rad = env.q_min_rad.cwiseMin(s.q_min_rad);
    env.q_max_rad = env.q_max_rad.cwiseMax(s.q_max_rad);
    env.qd_max_radps = env.qd_max_radps.cwiseMax(s.qd_max_radps);
    env.qdd_max_radps2 = env.qdd_max_radps2.cwiseMax(s.qdd_max_radps2);
    if (t.locked_joints == 0) env.tau_max_Nm[0] = std::max(env.tau_max_Nm[0], s.tau_max_Nm[0]);
    env.tau_max_Nm[1] = std::max(env.tau_max_Nm[1], s.tau_max_Nm[1]);
  }
  return env;
}

Eigen::VectorXd excitationCrb(const core::FourierSeries& t, const ident::Robot& robot, double duration_s, double rate_hz,
                              double sigma_Nm) {
  const int samples = static_cast<int>(std::lround(t.period_s() * rate_hz));
  const Eigen::MatrixXd H = ident::excitationRegressor(robot, t, samples);
  const double periods = duration_s / t.period_s();
  const Eigen::MatrixXd info = periods * H.transpose() * H / (sigma_Nm * sigma_Nm);
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(info);
  const Eigen::MatrixXd cov = ldlt.solve(Eigen::MatrixXd::Identity(info.rows(), info.cols()));
  return cov.diagonal().cwiseMax(0.0).cwiseSqrt();
}

}  // namespace exoid::experiments
