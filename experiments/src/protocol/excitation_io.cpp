#include "exoid/experiments/protocol/excitation_io.hpp"
#include "exoid/experiments/protocol/identification.hpp"

#include <Eigen/Cholesky>

#include <cmath>
#include <stdexcept>

namespace exoid::experiments {

nlohmann::json toJson(const core::FourierSeries& t) {
  const auto col = [](const Eigen::MatrixXd& m, int j) {
    std::vector<double> v(static_cast<std::size_t>(m.rows()));
    for (Eigen::Index k = 0; k < m.rows(); ++k) v[static_cast<std::size_t>(k)] = m(k, j);
    return v;
  };
  return {{"f0_hz", t.f0_hz},
          {"hip_locked", t.locked_joints > 0},
          {"offset_rad", {{"hip", t.offset_rad[0]}, {"knee", t.offset_rad[1]}}},
          {"a_rad", {{"hip", col(t.a_rad, 0)}, {"knee", col(t.a_rad, 1)}}},
          {"b_rad", {{"hip", col(t.b_rad, 0)}, {"knee", col(t.b_rad, 1)}}}};
}

core::FourierSeries readExcitationFile(const std::string& path) {
  const nlohmann::json j = readUserJsonFile(path, "excitation file");
  if (!j.is_object() || !j.contains("trajectory") || !j["trajectory"].is_object()) {
    throw std::invalid_argument(path + ": expected an object with a \"trajectory\" object (as exoid excite writes)");
  }
  const nlohmann::json& t = j["trajectory"];
  const auto need = [&](const char* key) -> const nlohmann::json& {
    if (!t.contains(key)) throw std::invalid_argument(path + ": trajectory." + key + " is missing");
    return t[key];
  };
  core::FourierSeries out;
  try {
    const double f0_hz = need("f0_hz").get<double>();
    const bool hip_locked = need("hip_locked").get<bool>();
    const double hip_offset = need("offset_rad").at("hip").get<double>(), knee_offset = need("offset_rad").at("knee").get<double>();
    const auto hip_a = need("a_rad").at("hip").get<std::vector<double>>(), knee_a = need("a_rad").at("knee").get<std::vector<double>>();
    const auto hip_b = need("b_rad").at("hip").get<std::vector<double>>(), knee_b = need("b_rad").at("knee").get<std::vector<double>>();
    const std::size_t n = hip_a.size();
    if (n == 0 || knee_a.size() != n || hip_b.size() != n || knee_b.size() != n) {
      throw std::invalid_argument("a_rad and b_rad need the same number (>= 1) of harmonics for hip and knee");
    }
    out = core::FourierSeries::still(2, static_cast<int>(n), f0_hz);
    out.locked_joints = hip_locked ? 1 : 0;
    out.offset_rad << hip_offset, knee_offset;
    for (std::size_t k = 0; k < n; ++k) {
      const auto K = static_cast<Eigen::Index>(k);
      out.a_rad.row(K) << hip_a[k], knee_a[k];
      out.b_rad.row(K) << hip_b[k], knee_b[k];
    }
    out.validate();
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(path + ": trajectory: " + e.what());
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": trajectory: " + e.what());
  }
  return out;
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

Eigen::VectorXd excitationCrb(const core::FourierSeries& t, const ident::LegConstants& c, double duration_s,
                              double rate_hz, double sigma_Nm) {
  const int samples = static_cast<int>(std::lround(t.period_s() * rate_hz));
  const Eigen::MatrixXd H = ident::excitationRegressor(ident::twoLinkLeg(c), t, samples);
  const double periods = duration_s / t.period_s();
  const Eigen::MatrixXd info = periods * H.transpose() * H / (sigma_Nm * sigma_Nm);
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(info);
  const Eigen::MatrixXd cov = ldlt.solve(Eigen::MatrixXd::Identity(info.rows(), info.cols()));
  return cov.diagonal().cwiseMax(0.0).cwiseSqrt();
}

}  // namespace exoid::experiments
