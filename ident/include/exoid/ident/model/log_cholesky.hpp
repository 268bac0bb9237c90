#pragma once
// A link's 10 standard parameters as its pseudo-inertia matrix and the log-Cholesky coordinates
// of it (Wensing, Kim and Slotine 2017; Rucker and Wensing 2022):
//   J = [[Sigma, h], [h', m]],  Sigma = tr(I)/2 1 - I,  h = m c  (I about the link frame's origin).
// A body with a real (non-negative) mass density has J >= 0; exoid calls a link consistent when
// J > 0. J = U U' with U upper triangular,
//   U = e^alpha [[e^d1, s12, s13, t1], [0, e^d2, s23, t2], [0, 0, e^d3, t3], [0, 0, 0, 1]],
// maps theta = (alpha, d1, d2, d3, s12, s23, s13, t1, t2, t3), any 10 reals, one to one onto the
// positive definite J: an unconstrained search over theta never leaves the consistent set.
#include "exoid/ident/model/chain.hpp"

#include <Eigen/Core>

namespace exoid::ident {

using LinkVector = Eigen::Matrix<double, kLinkParams, 1>;

/// J of a link's standard parameters (linear in them).
Eigen::Matrix4d pseudoInertia(const LinkVector& phi);
/// The standard parameters of a J (linear; the inverse of pseudoInertia).
LinkVector linkFromPseudoInertia(const Eigen::Matrix4d& J);
/// The smallest eigenvalue of J: > 0 for a consistent link (its units are kg m^2 for the
/// rotational block; compare it with the link's own scale).
double pseudoInertiaMinEigenvalue(const LinkVector& phi);

/// phi(theta), and its 10 x 10 Jacobian d phi / d theta.
LinkVector linkFromLogCholesky(const LinkVector& theta);
Eigen::Matrix<double, kLinkParams, kLinkParams> linkFromLogCholeskyJacobian(const LinkVector& theta);
/// theta(phi) of a consistent link (J > 0); throws std::invalid_argument naming the smallest
/// eigenvalue otherwise.
LinkVector logCholeskyFromLink(const LinkVector& phi);

}  // namespace exoid::ident
