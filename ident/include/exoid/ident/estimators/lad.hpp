#pragma once
// The exact minimum of the paper's L1 cost: least absolute deviations, min_x sum_i |b_i - a_i^T x|.
// The cost is convex (a sum of absolute values of affine functions), so this is its global
// minimum; it is used to score each PSO run by its optimality gap.
#include "exoid/ident/estimators/summary.hpp"

#include <Eigen/Core>

namespace exoid::ident {

struct LadOptions {
  /// Stop when (primal - dual) <= gap_tolerance * max(1, |primal|), or when the gap is below the
  /// rounding level of the cost itself, (p + 1) eps sum_i (|b_i| + |a_i|^T |x|), which no double
  /// precision x can beat. Range (0, 1). Default 1e-10.
  double gap_tolerance = 1e-10;
  /// Interior-point iteration limit (each solves one p x p system). Range >= 1. Default 100;
  /// measured 5-15 on noisy regressor data, up to ~50 on badly posed ones (huge optimal x).
  int max_iterations = 100;
  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

struct LadResult {
  Eigen::VectorXd x;        ///< minimiser (x = 0 when the status is kRankDeficient)
  double cost = 0.0;        ///< sum |b - A x| at x (primal objective)
  /// b^T u - |x|^T |A^T u| for a u with |u_i| <= 1 exactly and A^T u = 0 up to roundoff (the
  /// leftover A^T u is charged at its worst sign): cost >= optimum >= dual_bound.
  double dual_bound = 0.0;
  double gap = 0.0;         ///< cost - dual_bound >= 0: the certificate
  /// The u (size N, |u_i| <= 1 exactly) that gave dual_bound, so a caller can re-check the
  /// certificate or reuse it (the boxed solver does); all zero when the status is kRankDeficient.
  Eigen::VectorXd dual;
  Summary summary;          ///< iterations, cost at the least-squares start, final cost, time
};

/// Solves min ||b - A x||_1 by a primal-dual interior-point method on its linear program
/// (Frisch-Newton, Portnoy & Koenker 1997, with Mehrotra's predictor-corrector): each iteration
/// solves one p x p weighted normal system, so the work is O(N p^2) per iteration. The columns
/// of A are scaled internally. After it converges, the solution is purified to the vertex through
/// the p rows with the smallest residuals when that is no worse, and the dual bound is taken from
/// the better of the interior point's dual and that vertex's basic dual.
/// Status: kConverged when the gap meets LadOptions::gap_tolerance; kMaxIterations otherwise (x is
/// the best point found and gap is its honest certificate); kRankDeficient when the column-scaled
/// A has rank < p (pivoted QR, relative pivot tolerance 1e-8; the message names the dependent
/// columns). Throws std::invalid_argument on an empty A, size mismatch or non-finite input.
LadResult solveLeastAbsoluteDeviations(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                                       const LadOptions& options = {});

}  // namespace exoid::ident
