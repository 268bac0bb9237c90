#include "exoid/sim/actuators.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace exoid::sim {

void ActuatorOptions::validate(double dt_s) const {
  auto check = [dt_s](const char* name, double bw, const char* zname, double zeta) {
    const double nyquist = 0.5 / dt_s;
    if (!(std::isfinite(bw) && bw >= 0.0 && bw < nyquist)) {
      std::ostringstream ss;
      ss.precision(17);
      ss << "'" << name << "' must be in [0, " << nyquist << ") Hz (0 = ideal actuator), got " << bw;
      throw std::invalid_argument(ss.str());
    }
    if (!(std::isfinite(zeta) && zeta > 0.0)) {
      std::ostringstream ss;
      ss << "'" << zname << "' must be > 0, got " << zeta;
      throw std::invalid_argument(ss.str());
    }
  };
  check("actuators.hip_bandwidth_Hz", hip_bandwidth_Hz, "actuators.hip_damping", hip_damping);
  check("actuators.knee_bandwidth_Hz", knee_bandwidth_Hz, "actuators.knee_damping", knee_damping);
}

namespace {
SecondOrderLowpass lag(const ActuatorOptions& o, int joint, double dt_s) {
  o.validate(dt_s);
  return joint == 0 ? SecondOrderLowpass(o.hip_bandwidth_Hz, o.hip_damping, dt_s)
                    : SecondOrderLowpass(o.knee_bandwidth_Hz, o.knee_damping, dt_s);
}
}  // namespace

Actuators::Actuators(const ActuatorOptions& o, double dt_s) : lag_{lag(o, 0, dt_s), lag(o, 1, dt_s)} {
  const double bw[2] = {o.hip_bandwidth_Hz, o.knee_bandwidth_Hz};
  const double zeta[2] = {o.hip_damping, o.knee_damping};
  for (int j = 0; j < 2; ++j) {
    const double wn = 2.0 * M_PI * bw[j];
    lead1_[j] = bw[j] > 0.0 ? 2.0 * zeta[j] / wn : 0.0;
    lead2_[j] = bw[j] > 0.0 ? 1.0 / (wn * wn) : 0.0;
  }
}

void Actuators::reset(const Eigen::Vector2d& tau) {
  for (int j = 0; j < 2; ++j) lag_[static_cast<std::size_t>(j)].reset(tau[j]);
}

Eigen::Vector2d Actuators::step(const Eigen::Vector2d& u) {
  return {lag_[0].step(u[0]), lag_[1].step(u[1])};
}

Eigen::Vector2d Actuators::inverse(const Eigen::Vector2d& tau, const Eigen::Vector2d& tau_dot,
                                   const Eigen::Vector2d& tau_ddot) const {
  return tau + lead1_.cwiseProduct(tau_dot) + lead2_.cwiseProduct(tau_ddot);
}

}  // namespace exoid::sim
