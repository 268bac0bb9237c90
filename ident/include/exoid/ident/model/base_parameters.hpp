#pragma once
// The identifiable combinations of a chain's standard parameters (its base parameters), from the
// regressor over random states by QR with column pivoting (Gautier 1990; Khalil and Dombre ch. 12):
// W P = Q [R1 R2], rank r, W2 = W1 K with K = R1^-1 R2, so tau = W1 (phi1 + K phi2) and the base
// parameters are beta = phi1 + K phi2. The space they span (the row space of W) is unique; the
// choice of phi1 follows the pivoting.
#include "exoid/ident/model/chain.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace exoid::ident {

struct BaseParameterOptions {
  /// Random states drawn (q uniform in [-pi, pi], qd in [-3, 3] rad/s, qdd in [-30, 30] rad/s^2).
  /// Range >= standardParameterCount(). Default 200: many more rows than a chain of <= 7 joints
  /// has columns (~90), so a rank found is the rank of the model, not of the sample.
  int samples = 200;
  std::uint64_t seed = 1;  ///< the states' seed: same seed, same combinations
  /// A pivot |R_ii| <= tolerance |R_00| counts as zero. Range (0, 1). Default 1e-9: random-state
  /// regressors of chains with O(0.01..1 m) geometry have genuine pivots above 1e-6 of the first,
  /// while regrouped columns leave roundoff (~1e-14).
  double tolerance = 1e-9;
  /// Coefficients of K below this magnitude are written as zero. Default 1e-10.
  double coefficient_tolerance = 1e-10;
  /// The states' base moves in its x-z plane and turns about its y axis (what a planar IMU's
  /// columns describe, and what the regressor then sees): a link's inertia and its joint's
  /// armature, which a still base regroups (the link turns with its joint alone), separate (the
  /// link turns with the base too). For records with base-motion terms. Default false.
  bool planar_base_motion = false;
  void validate() const;  ///< throws std::invalid_argument naming the field
};

struct BaseParameters {
  int rank = 0;
  /// Standard parameter index each base parameter is named after (phi1), in pivot order.
  std::vector<int> independent;
  /// rank x standardParameterCount(): beta = combination * phi.
  Eigen::MatrixXd combination;
  /// Each base parameter's short, stable label: its leading standard parameter, and "+ N terms"
  /// when others are regrouped into it ("shank.Iyy", "thigh.Iyy + 1 term"). Distinct (the leads are).
  std::vector<std::string> names;
  /// Each row of `combination` in words, the label's full meaning ("thigh.Iyy + 0.2025 shank.m").
  std::vector<std::string> combinations;
  /// Standard parameters that move no joint torque at all (a zero column): nothing identifies them.
  std::vector<int> no_effect;
  /// Standard parameters that act only through others (dependent columns with a nonzero K):
  /// each with the base parameters it is regrouped into.
  std::vector<std::pair<int, std::vector<int>>> regrouped;
  /// The base regressor of a state's standard regressor Y: Y's independent columns.
  Eigen::MatrixXd baseRegressor(const Eigen::MatrixXd& Y) const;
};

/// Throws std::invalid_argument on an invalid model or options.
BaseParameters baseParameters(const ChainModel& model, const BaseParameterOptions& options = {});

}  // namespace exoid::ident
