#include "exoid/sim/vibration.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace exoid::sim {

void FloorDisturbance::validate() const {
  auto check = [](const char* name, double v, bool ok, const char* expected) {
    if (!ok) {
      std::ostringstream ss;
      ss << "'floor." << name << "' must be " << expected << ", got " << v;
      throw std::invalid_argument(ss.str());
    }
  };
  check("force_x_amplitude_N", force_x_amplitude_N, std::isfinite(force_x_amplitude_N) && force_x_amplitude_N >= 0, ">= 0");
  check("force_z_amplitude_N", force_z_amplitude_N, std::isfinite(force_z_amplitude_N) && force_z_amplitude_N >= 0, ">= 0");
  check("frequency_Hz", frequency_Hz, std::isfinite(frequency_Hz) && frequency_Hz > 0, "> 0");
  check("random_std_N", random_std_N, std::isfinite(random_std_N) && random_std_N >= 0, ">= 0");
}

FloorForce::FloorForce(const FloorDisturbance& f, std::uint64_t seed)
    : f_(f), rng_(streamSeed(seed, kStreamFloor)) {
  f.validate();
}

void FloorForce::at(double t_s, double& fx, double& fz) {
  const double s = std::sin(2 * M_PI * f_.frequency_Hz * t_s);
  fx = f_.force_x_amplitude_N * s;
  fz = f_.force_z_amplitude_N * s;
  if (f_.random_std_N > 0) {
    fx += f_.random_std_N * rng_.normal();
    fz += f_.random_std_N * rng_.normal();
  }
}

}  // namespace exoid::sim
