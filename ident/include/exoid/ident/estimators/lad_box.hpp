#pragma once
// The exact minimum of the paper's L1 cost over a box:
//   min_x ||b - A x||_1  subject to  lower <= x <= upper.
// PSO searches a box, so its optimality gap is measured against this optimum, not the
// unconstrained one (which may lie outside the box and be out of PSO's reach).
#include "exoid/ident/estimators/box.hpp"
#include "exoid/ident/estimators/lad.hpp"

#include <Eigen/Core>

#include <vector>

namespace exoid::ident {

struct BoxedLadResult : LadResult {
  /// Per parameter: -1 when x_j == box.lower_j, +1 when x_j == box.upper_j, 0 inside. A solution
  /// coordinate within 1e-9 of the box width from a bound is put exactly on it when that leaves
  /// the cost within its rounding level, so this flags the estimates the box stopped, not those
  /// the data hold just inside it.
  std::vector<int> at_bound;
  /// How many entries of at_bound are nonzero.
  int activeBounds() const;
};

/// Solves min ||b - A x||_1 over the box lower <= x <= upper, exactly, with a certificate.
///
/// Method (exact penalty): for each column j two rows c_j e_j^T with right-hand sides c_j upper_j
/// and c_j lower_j, c_j = ||A_j||_1, are appended and the unconstrained solver runs on the result.
/// Inside the box the two rows add the constant c_j (upper_j - lower_j); beyond a bound they grow
/// with slope 2 c_j, more than the data cost can fall (by at most ||A_j||_1 per unit of x_j), so
/// the penalised minimiser lies in the box and is the box minimiser. x is clamped into the box
/// (rounding) and put on the bounds it is within 1e-9 of the width from when that costs nothing
/// beyond rounding. The penalty rows' own rounding (~eps c_j max(|lower_j|, |upper_j|)) can hide
/// the last digits of the cost when the box is far wider than |x|; only then (the certificate
/// falls short) a short active-set iteration follows: hold the bounds the point sits on (less
/// those whose multiplier says the cost falls inwards), solve the rest without penalty rows,
/// repeat (at most p + 1 rounds); the best point and the best bound found are kept.
///
/// Result fields refer to the data rows only: cost = ||b - A x||_1; dual holds a u of size N with
/// |u_i| <= 1 and dual_bound = b^T u - sum_j max(lower_j g_j, upper_j g_j), g = A^T u, which
/// bounds the box optimum from below by weak duality (sums in long double), so anyone can re-check
/// it; gap = cost - dual_bound. summary.iterations counts all interior-point iterations;
/// summary.initial_cost is the cost at the box centre (a feasible reference point).
/// Status: kConverged when gap <= gap_tolerance * max(1, cost) or below the rounding level of the
/// cost (as for the unconstrained solver); kMaxIterations otherwise (x is the best point found,
/// gap its honest certificate; also the outcome, with a gap of ~1e-10 relative, when bounds
/// ~1e8 times |x| leave a double-precision dual too coarse); kRankDeficient only if the penalised
/// problem is (it has full rank by construction; x is then the box point nearest 0). A
/// rank-deficient A is fine here: the box bounds every direction the data cannot see (x is then
/// one of several minimisers, possibly on far bounds along the null direction).
/// Throws std::invalid_argument on an empty A, size mismatches, non-finite input, a box whose
/// lower_j >= upper_j, or invalid options.
BoxedLadResult solveBoxedLeastAbsoluteDeviations(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                                                 const Box& box, const LadOptions& options = {});

}  // namespace exoid::ident
