#pragma once
// The exact minimum of the paper's L1 cost: least absolute deviations, min_x sum_i |b_i - a_i^T x|.
// The cost is convex (a sum of absolute values of affine functions), so this is its global
// minimum; it is used to score each PSO run by its optimality gap.
#include "exoid/ident/summary.hpp"

#include <Eigen/Core>

namespace exoid::ident {

struct LadOptions {
  /// Stop when (primal - dual) <= gap_tolerance * max(1, |primal|). Range (0, 1). Default 1e-10.
  double gap_tolerance = 1e-10;
  /// Interior-point iteration limit (each solves one p x p system). Range >= 1. Default 100.
  int max_iterations = 100;
  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

struct LadResult {
  Eigen::VectorXd x;        ///< minimiser
  double cost = 0.0;        ///< sum |b - A x| at x (primal objective)
  double dual_bound = 0.0;  ///< b^T u for a dual-feasible u (A^T u = 0, |u_i| <= 1): cost >= optimum >= dual_bound
  double gap = 0.0;         ///< cost - dual_bound >= 0: the certificate
  Summary summary;
};

/// Solves min ||b - A x||_1 by a primal-dual interior-point method on its linear program
/// (Frisch-Newton, Portnoy & Koenker 1997): each iteration solves a p x p weighted normal system.
/// Throws std::invalid_argument on size mismatch or non-finite input. Rank deficient A gives
/// Status::kRankDeficient.
LadResult solveLeastAbsoluteDeviations(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                                       const LadOptions& options = {});

}  // namespace exoid::ident
