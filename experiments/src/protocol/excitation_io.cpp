#include "exoid/experiments/protocol/excitation_io.hpp"
#include "exoid/experiments/protocol/identification.hpp"

#include <Eigen/Cholesky>

#include <cmath>
#include <stdexcept>

namespace exoid::experiments {

sim::FourierSpec toFourierSpec(const ident::FourierTrajectory& t) {
  t.validate();
  sim::FourierSpec s;
  s.base_frequency_Hz = t.f0_hz;
  s.lock_hip = t.hip_locked;
  sim::FourierJoint* joints[2] = {&s.hip, &s.knee};
  for (int j = 0; j < 2; ++j) {
    joints[j]->offset_rad = t.offset_rad[j];
    for (Eigen::Index k = 0; k < t.a_rad.rows(); ++k) {
      joints[j]->a_rad.push_back(t.a_rad(k, j));
      joints[j]->b_rad.push_back(t.b_rad(k, j));
    }
  }
  return s;
}

ident::FourierTrajectory toFourierTrajectory(const sim::FourierSpec& s) {
  ident::FourierTrajectory t;
  t.f0_hz = s.base_frequency_Hz;
  t.hip_locked = s.lock_hip;
  const sim::FourierJoint* joints[2] = {&s.hip, &s.knee};
  const std::size_t n = std::max({s.hip.a_rad.size(), s.knee.a_rad.size(), std::size_t{1}});
  t.a_rad = Eigen::MatrixX2d::Zero(static_cast<Eigen::Index>(n), 2);
  t.b_rad = Eigen::MatrixX2d::Zero(static_cast<Eigen::Index>(n), 2);
  for (int j = 0; j < 2; ++j) {
    t.offset_rad[j] = joints[j]->offset_rad;
    for (std::size_t k = 0; k < joints[j]->a_rad.size(); ++k) t.a_rad(static_cast<Eigen::Index>(k), j) = joints[j]->a_rad[k];
    for (std::size_t k = 0; k < joints[j]->b_rad.size(); ++k) t.b_rad(static_cast<Eigen::Index>(k), j) = joints[j]->b_rad[k];
  }
  return t;
}

nlohmann::json toJson(const ident::FourierTrajectory& t) {
  const auto col = [](const Eigen::MatrixX2d& m, int j) {
    std::vector<double> v(static_cast<std::size_t>(m.rows()));
    for (Eigen::Index k = 0; k < m.rows(); ++k) v[static_cast<std::size_t>(k)] = m(k, j);
    return v;
  };
  return {{"f0_hz", t.f0_hz},
          {"hip_locked", t.hip_locked},
          {"offset_rad", {{"hip", t.offset_rad[0]}, {"knee", t.offset_rad[1]}}},
          {"a_rad", {{"hip", col(t.a_rad, 0)}, {"knee", col(t.a_rad, 1)}}},
          {"b_rad", {{"hip", col(t.b_rad, 0)}, {"knee", col(t.b_rad, 1)}}}};
}

ident::FourierTrajectory readExcitationFile(const std::string& path) {
  const nlohmann::json j = readUserJsonFile(path, "excitation file");
  if (!j.is_object() || !j.contains("trajectory") || !j["trajectory"].is_object()) {
    throw std::invalid_argument(path + ": expected an object with a \"trajectory\" object (as exoid excite writes)");
  }
  const nlohmann::json& t = j["trajectory"];
  const auto need = [&](const char* key) -> const nlohmann::json& {
    if (!t.contains(key)) throw std::invalid_argument(path + ": trajectory." + key + " is missing");
    return t[key];
  };
  ident::FourierTrajectory out;
  try {
    out.f0_hz = need("f0_hz").get<double>();
    out.hip_locked = need("hip_locked").get<bool>();
    out.offset_rad << need("offset_rad").at("hip").get<double>(), need("offset_rad").at("knee").get<double>();
    const auto hip_a = need("a_rad").at("hip").get<std::vector<double>>(), knee_a = need("a_rad").at("knee").get<std::vector<double>>();
    const auto hip_b = need("b_rad").at("hip").get<std::vector<double>>(), knee_b = need("b_rad").at("knee").get<std::vector<double>>();
    const std::size_t n = hip_a.size();
    if (n == 0 || knee_a.size() != n || hip_b.size() != n || knee_b.size() != n) {
      throw std::invalid_argument("a_rad and b_rad need the same number (>= 1) of harmonics for hip and knee");
    }
    out.a_rad.resize(static_cast<Eigen::Index>(n), 2);
    out.b_rad.resize(static_cast<Eigen::Index>(n), 2);
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
  wide.q_min_rad.setConstant(-10.0);
  wide.q_max_rad.setConstant(10.0);
  wide.qd_max_radps.setConstant(1e9);
  wide.qdd_max_radps2.setConstant(1e9);
  wide.tau_max_Nm.setConstant(1e9);
  ident::ExcitationLimits env;
  env.q_min_rad.setConstant(1e9);
  env.q_max_rad.setConstant(-1e9);
  env.qd_max_radps.setZero();
  env.qdd_max_radps2.setZero();
  env.tau_max_Nm.setZero();
  for (int id = 1; id <= 4; ++id) {
    const ident::FourierTrajectory t = toFourierTrajectory(sim::paperTrajectory(id));
    const ident::ExcitationScore s = ident::scoreExcitation(t, c, nominal, wide, 1000);
    env.q_min_rad = env.q_min_rad.cwiseMin(s.q_min_rad);
    env.q_max_rad = env.q_max_rad.cwiseMax(s.q_max_rad);
    env.qd_max_radps = env.qd_max_radps.cwiseMax(s.qd_max_radps);
    env.qdd_max_radps2 = env.qdd_max_radps2.cwiseMax(s.qdd_max_radps2);
    if (!t.hip_locked) env.tau_max_Nm[0] = std::max(env.tau_max_Nm[0], s.tau_max_Nm[0]);
    env.tau_max_Nm[1] = std::max(env.tau_max_Nm[1], s.tau_max_Nm[1]);
  }
  return env;
}

Eigen::VectorXd excitationCrb(const ident::FourierTrajectory& t, const ident::LegConstants& c, double duration_s,
                              double rate_hz, double sigma_Nm) {
  const int samples = static_cast<int>(std::lround(t.period_s() * rate_hz));
  const Eigen::MatrixXd H = ident::excitationRegressor(t, c, samples);
  const double periods = duration_s / t.period_s();
  const Eigen::MatrixXd info = periods * H.transpose() * H / (sigma_Nm * sigma_Nm);
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(info);
  const Eigen::MatrixXd cov = ldlt.solve(Eigen::MatrixXd::Identity(info.rows(), info.cols()));
  return cov.diagonal().cwiseMax(0.0).cwiseSqrt();
}

}  // namespace exoid::experiments
