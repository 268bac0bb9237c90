#pragma once
// Bounded particle swarm optimisation (paper Eq. 7-8) with linearly decreasing inertia.
#include "exoid/ident/estimators/box.hpp"
#include "exoid/ident/estimators/summary.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <vector>

namespace exoid::ident {

/// Evaluates a whole swarm: particles is p x S (one column per particle), costs has S entries.
using BatchCost = std::function<void(const Eigen::Ref<const Eigen::MatrixXd>& particles,
                                     Eigen::Ref<Eigen::VectorXd> costs)>;

enum class BoundaryPolicy {
  kClamp,    ///< the paper: a position outside the box is reset to the nearest bound
  kReflect,  ///< mirrored back into the box and the velocity component reversed
};
const char* toString(BoundaryPolicy p);

struct PsoOptions {
  int swarm_size = 40;           ///< S, particles. Range >= 2. (Not given by the paper.)
  long max_iterations = 10000;   ///< G (paper). Range >= 1.
  double cost_tolerance = 1e-2;  ///< stop when the best cost < this (paper). Range >= 0.
  double w_max = 0.9;            ///< inertia at iteration 0, falls linearly to w_min at G. Range (0, 2).
  double w_min = 0.4;            ///< inertia at the last iteration. Range (0, w_max].
  double c1 = 2.0;               ///< cognitive (personal best) weight. Range >= 0.
  double c2 = 2.0;               ///< social (global best) weight. Range >= 0.
  /// Velocity range: |v_k| <= velocity_fraction * (upper_k - lower_k). Range (0, 1].
  double velocity_fraction = 0.2;
  BoundaryPolicy boundary = BoundaryPolicy::kClamp;
  std::uint64_t seed = 1;        ///< every draw comes from this seed (xoshiro256**)
  bool keep_history = true;      ///< best cost after each iteration
  void validate() const;         ///< throws std::invalid_argument naming the field
};

struct PsoResult {
  Eigen::VectorXd x;                     ///< best position found
  double cost = 0.0;                     ///< its cost
  std::vector<double> best_cost_history;  ///< best cost after initialisation and each iteration
  long evaluations = 0;
  Summary summary;
};

/// Minimises `cost` inside `box`. Positions start uniform in the box, velocities uniform in the
/// velocity range. Deterministic for a given seed. Status kConverged if the best cost fell
/// below cost_tolerance, else kMaxIterations.
PsoResult minimizePso(const BatchCost& cost, const Box& box, const PsoOptions& options);

}  // namespace exoid::ident
