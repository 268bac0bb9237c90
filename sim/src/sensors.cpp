#include "exoid/sim/sensors.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

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
  check("tau_bias_Nm[hip]", tau_bias_Nm[0], std::isfinite(tau_bias_Nm[0]) && std::abs(tau_bias_Nm[0]) <= 1e3, "in [-1000, 1000] N m");
  check("tau_bias_Nm[knee]", tau_bias_Nm[1], std::isfinite(tau_bias_Nm[1]) && std::abs(tau_bias_Nm[1]) <= 1e3, "in [-1000, 1000] N m");
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

Sensors::Sensors(const SensorOptions& o, std::uint64_t seed, double dt_s)
    : o_(o),
      noise_q_rad_(o.noise_q_deg * M_PI / 180.0),
      quant_rad_(o.quantisation_deg * M_PI / 180.0),
      backlash_rad_(o.encoder_backlash_deg * M_PI / 180.0),
      enc_(streamSeed(seed, kStreamEncoder)),
      tau_(streamSeed(seed, kStreamTorque)),
      imu_(streamSeed(seed, kStreamImu)),
      tau_filter_{torqueFilter(o, dt_s), torqueFilter(o, dt_s)} {}

void Sensors::resetTorqueFilters(const Eigen::Vector2d& tau) {
  for (int j = 0; j < 2; ++j) tau_filter_[static_cast<std::size_t>(j)].reset(tau[j]);
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

Eigen::Vector2d Sensors::angles(const Eigen::Vector2d& q) {
  Eigen::Vector2d out;
  for (int j = 0; j < 2; ++j) {
    double v = q[j];
    if (backlash_rad_ > 0) {
      double& r = play_[static_cast<std::size_t>(j)];
      r = play_started_ ? std::clamp(r, v - 0.5 * backlash_rad_, v + 0.5 * backlash_rad_) : v;
      v = r;
    }
    if (noise_q_rad_ > 0) v += noise_q_rad_ * enc_.normal();
    if (quant_rad_ > 0) v = std::nearbyint(v / quant_rad_) * quant_rad_;
    out[j] = v;
  }
  play_started_ = true;
  return out;
}

Eigen::Vector2d Sensors::torques(const Eigen::Vector2d& tau) {
  Eigen::Vector2d out;
  for (int j = 0; j < 2; ++j) {
    double v = tau_filter_[static_cast<std::size_t>(j)].step(tau[j]) + o_.tau_bias_Nm[static_cast<std::size_t>(j)];
    if (o_.noise_tau_Nm > 0) v += o_.noise_tau_Nm * tau_.normal();
    out[j] = v;
  }
  return out;
}

}  // namespace exoid::sim
