#pragma once
// Pedestal vibration: the compliant mount (ModelVariant::vibration_level) and an optional
// external floor disturbance, a force on the pedestal's COM:
//   F_x(t) = Ax sin(2 pi f t) + nx_k,  F_z(t) = Az sin(2 pi f t) + nz_k,
// with nx_k, nz_k i.i.d. N(0, random_std_N^2) drawn once per sample (held for one step; white
// up to the Nyquist frequency), from the seed's kStreamFloor stream.
#include "exoid/sim/random.hpp"

#include <cstdint>

namespace exoid::sim {

struct FloorDisturbance {
  double force_x_amplitude_N = 0.0;  ///< >= 0
  double force_z_amplitude_N = 0.0;  ///< >= 0
  double frequency_Hz = 8.0;         ///< > 0
  double random_std_N = 0.0;         ///< >= 0
  bool active() const { return force_x_amplitude_N > 0 || force_z_amplitude_N > 0 || random_std_N > 0; }
  void validate() const;
};

class FloorForce {
 public:
  FloorForce(const FloorDisturbance& f, std::uint64_t seed);
  /// Force (N) at sample time t: [Fx, Fz].
  void at(double t_s, double& fx, double& fz);

 private:
  FloorDisturbance f_;
  Rng rng_;
};

}  // namespace exoid::sim
