#pragma once
// Joint sensors at the control rate: encoders and joint torque sensors. They see the joint
// quantities only, never the pedestal motion.
#include "exoid/sim/random.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>

namespace exoid::sim {

struct SensorOptions {
  /// Encoder white noise, standard deviation (deg), >= 0. Added before quantisation.
  double noise_q_deg = 0.0;
  /// Encoder resolution (deg per count), >= 0; 0 = no quantisation. Reading = round(x/r) r.
  double quantisation_deg = 0.0;
  /// Torque sensor white noise, standard deviation (N m), >= 0.
  double noise_tau_Nm = 0.0;
  /// Constant torque sensor bias (N m), hip and knee; finite.
  std::array<double, 2> tau_bias_Nm{0.0, 0.0};
  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

class Sensors {
 public:
  Sensors(const SensorOptions& o, std::uint64_t seed);
  /// Encoder readings (rad) of the true angles (rad).
  Eigen::Vector2d angles(const Eigen::Vector2d& q_true_rad);
  /// Torque readings (N m) of the true motor torques.
  Eigen::Vector2d torques(const Eigen::Vector2d& tau_true_Nm);

 private:
  SensorOptions o_;
  double noise_q_rad_, quant_rad_;
  Rng enc_, tau_;
};

}  // namespace exoid::sim
