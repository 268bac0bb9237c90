#include "exoid/sim/sensors.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace exoid::sim {

void SensorOptions::validate() const {
  auto check = [](const char* name, double v, bool ok, const char* expected) {
    if (!ok) {
      std::ostringstream ss;
      ss.precision(17);
      ss << "'" << name << "' must be " << expected << ", got " << v;
      throw std::invalid_argument(ss.str());
    }
  };
  check("noise_q_deg", noise_q_deg, std::isfinite(noise_q_deg) && noise_q_deg >= 0 && noise_q_deg < 90, "in [0, 90)");
  check("quantisation_deg", quantisation_deg,
        std::isfinite(quantisation_deg) && quantisation_deg >= 0 && quantisation_deg < 90, "in [0, 90)");
  check("encoder_backlash_deg", encoder_backlash_deg,
        std::isfinite(encoder_backlash_deg) && encoder_backlash_deg >= 0 && encoder_backlash_deg < 90, "in [0, 90)");
  // Physical bounds, so that no setting can put an infinite or absurd number into a record: a
  // torque sensor noisier than 1 kN m (or biased more) measures nothing of a leg.
  check("noise_tau_Nm", noise_tau_Nm, std::isfinite(noise_tau_Nm) && noise_tau_Nm >= 0 && noise_tau_Nm <= 1e3, "in [0, 1000] N m");
  for (std::size_t j = 0; j < tau_bias_Nm.size(); ++j) {
    const std::string name = "tau_bias_Nm[" + std::to_string(j) + "]";
    check(name.c_str(), tau_bias_Nm[j], std::isfinite(tau_bias_Nm[j]) && std::abs(tau_bias_Nm[j]) <= 1e3, "in [-1000, 1000] N m");
  }
  check("tau_bandwidth_Hz", tau_bandwidth_Hz, std::isfinite(tau_bandwidth_Hz) && tau_bandwidth_Hz >= 0,
        ">= 0 (0 = ideal) and below the Nyquist frequency");
  check("imu_acc_noise_mps2", imu_acc_noise_mps2, std::isfinite(imu_acc_noise_mps2) && imu_acc_noise_mps2 >= 0 && imu_acc_noise_mps2 <= 1e3,
        "in [0, 1000] m/s^2");
  check("imu_gyro_noise_radps", imu_gyro_noise_radps,
        std::isfinite(imu_gyro_noise_radps) && imu_gyro_noise_radps >= 0 && imu_gyro_noise_radps <= 1e3, "in [0, 1000] rad/s");
}

namespace {
constexpr double kButterworthDamping = 0.70710678118654752;  // 1 / sqrt(2)

SecondOrderLowpass torqueFilter(const SensorOptions& o, double dt_s) {
  o.validate();
  return SecondOrderLowpass(o.tau_bandwidth_Hz, kButterworthDamping, dt_s);
}
}  // namespace

Sensors::Sensors(const SensorOptions& o, int joints, std::uint64_t seed, double dt_s)
    : o_(o),
      noise_q_rad_(o.noise_q_deg * M_PI / 180.0),
      quant_rad_(o.quantisation_deg * M_PI / 180.0),
      backlash_rad_(o.encoder_backlash_deg * M_PI / 180.0),
      play_(static_cast<std::size_t>(joints), 0.0),
      enc_(streamSeed(seed, kStreamEncoder)),
      tau_(streamSeed(seed, kStreamTorque)),
      imu_(streamSeed(seed, kStreamImu)),
      tau_filter_(static_cast<std::size_t>(joints), torqueFilter(o, dt_s)) {
  if (!o.tau_bias_Nm.empty() && static_cast<int>(o.tau_bias_Nm.size()) != joints) {
    throw std::invalid_argument("'tau_bias_Nm' has " + std::to_string(o.tau_bias_Nm.size()) + " values; the rig has " +
                                std::to_string(joints) + " joints");
  }
}

void Sensors::resetTorqueFilters(const Eigen::Ref<const Eigen::VectorXd>& tau) {
  for (std::size_t j = 0; j < tau_filter_.size(); ++j) tau_filter_[j].reset(tau[static_cast<Eigen::Index>(j)]);
}

Eigen::Vector3d Sensors::imu(const Eigen::Vector3d& truth) {
  Eigen::Vector3d out = truth;
  if (o_.imu_acc_noise_mps2 > 0) {
    out[0] += o_.imu_acc_noise_mps2 * imu_.normal();
    out[1] += o_.imu_acc_noise_mps2 * imu_.normal();
  }
  if (o_.imu_gyro_noise_radps > 0) out[2] += o_.imu_gyro_noise_radps * imu_.normal();
  return out;
}

void Sensors::angles(const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::Ref<Eigen::VectorXd> out) {
  for (std::size_t j = 0; j < play_.size(); ++j) {
    const auto i = static_cast<Eigen::Index>(j);
    double v = q[i];
    if (backlash_rad_ > 0) {
      double& r = play_[j];
      r = play_started_ ? std::clamp(r, v - 0.5 * backlash_rad_, v + 0.5 * backlash_rad_) : v;
      v = r;
    }
    if (noise_q_rad_ > 0) v += noise_q_rad_ * enc_.normal();
    if (quant_rad_ > 0) v = std::nearbyint(v / quant_rad_) * quant_rad_;
    out[i] = v;
  }
  play_started_ = true;
}

Eigen::VectorXd Sensors::angles(const Eigen::Ref<const Eigen::VectorXd>& q) {
  Eigen::VectorXd out(q.size());
  angles(q, out);
  return out;
}

Eigen::VectorXd Sensors::torques(const Eigen::Ref<const Eigen::VectorXd>& tau) {
  Eigen::VectorXd out(tau.size());
  torques(tau, out);
  return out;
}

void Sensors::torques(const Eigen::Ref<const Eigen::VectorXd>& tau, Eigen::Ref<Eigen::VectorXd> out) {
  for (std::size_t j = 0; j < tau_filter_.size(); ++j) {
    const auto i = static_cast<Eigen::Index>(j);
    double v = tau_filter_[j].step(tau[i]) + (o_.tau_bias_Nm.empty() ? 0.0 : o_.tau_bias_Nm[j]);
    if (o_.noise_tau_Nm > 0) v += o_.noise_tau_Nm * tau_.normal();
    out[i] = v;
  }
}

}  // namespace exoid::sim
