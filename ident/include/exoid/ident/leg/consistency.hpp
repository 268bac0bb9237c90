#pragma once
// Physically consistent least squares: the estimate of X closest to the data (in the LS sense)
// among those a real leg can have, and how far the unconstrained estimate is from that set in
// its own standard errors.
//
// With the thigh length Lt known, X comes from a real leg exactly when (docs/paper.md,
// "Physical consistency"):
//   fc1, fv1, fc2, fv2 >= 0                       friction dissipates
//   Js >= 0, Jt - Js >= 0                         inertias about the knee and the hip
//   (Jt - Js) Js >= Lt^2 (Mxs^2 + Mys^2)          some shank mass ms fits both: it needs
//                                                 Js >= (Mxs^2 + Mys^2) / ms (parallel axes)
//                                                 and Jt - Js >= ms Lt^2 (the shank at the knee)
// and, with the knee armature, Ia2 >= 0. The last is a rotated second-order cone, so the set is
// convex and the constrained problem has one minimum. It is solved by a log-barrier interior
// point (Newton on the 10 x 10 normal equations, column-scaled), Eigen only.
#include <Eigen/Core>

#include <string>
#include <vector>

namespace exoid::ident {

/// One condition g(x) >= 0 evaluated at the unconstrained estimate.
struct ConsistencyCheck {
  std::string name;            ///< e.g. "fv1 >= 0", "(Jt - Js) Js >= Lt^2 (Mxs^2 + Mys^2)"
  double value = 0.0;          ///< g at the unconstrained estimate (< 0: violated)
  double standard_error = 0.0;  ///< of g at that estimate (first order); +inf when unknown
  /// value / standard_error: how many standard errors inside (> 0) or outside (< 0) the set.
  double t() const;
  bool violated() const { return value < 0.0; }
  /// Violated by more than `sigmas` standard errors (the data contradict the physics).
  bool significant(double sigmas) const;
  bool active = false;  ///< the constrained estimate lies on this condition's boundary
};

struct ConsistencyOptions {
  /// A violation beyond this many standard errors is significant (not noise): the data, or the
  /// model, contradict the physics. Range > 0. Default 2 (a two-sided 95 % band).
  double significance_sigmas = 2.0;
  /// Relative duality gap at which the interior point stops: the constrained optimum's cost is
  /// within this fraction of ||y||^2. Range (0, 1e-3]. Default 1e-14.
  double gap_tolerance = 1e-14;
  void validate() const;  ///< throws std::invalid_argument naming the field
};

struct ConsistentEstimate {
  Eigen::VectorXd x;  ///< the constrained estimate; the unconstrained one when that is consistent
  std::vector<ConsistencyCheck> checks;  ///< every condition, at the unconstrained estimate
  bool constrained = false;  ///< x differs from the unconstrained estimate
  /// The conditions violated beyond options.significance_sigmas, each as
  /// "fv1 >= 0 violated by 3.1 standard errors (fv1 = -0.0032)".
  std::vector<std::string> significantViolations(double sigmas) const;
};

/// The consistency conditions of X (10 entries, or 11 with the knee armature Ia2 last).
/// g(x) and its gradient; thigh_length_m > 0.
struct ConsistencyConditions {
  explicit ConsistencyConditions(double thigh_length_m, bool knee_armature = false);
  int count() const;
  std::string name(int i) const;
  double value(int i, const Eigen::VectorXd& x) const;
  Eigen::VectorXd gradient(int i, const Eigen::VectorXd& x) const;
  /// Hessian of g_i (zero for the linear conditions).
  Eigen::MatrixXd hessian(int i, Eigen::Index n) const;
  bool satisfied(const Eigen::VectorXd& x) const;  ///< every g_i(x) >= 0
  double thigh_length_m;
  bool knee_armature;
};

/// min ||y - H x||^2 over the consistent set. x_ls is the unconstrained estimate and covariance
/// its covariance (for the standard errors; +inf entries allowed: then no violation is
/// significant). Returns x_ls itself when it satisfies every condition. Throws
/// std::invalid_argument on size mismatches, non-finite data or a rank-deficient H.
ConsistentEstimate solveConsistentLeastSquares(const Eigen::MatrixXd& H, const Eigen::VectorXd& y,
                                               double thigh_length_m, const Eigen::VectorXd& x_ls,
                                               const Eigen::MatrixXd& covariance,
                                               const ConsistencyOptions& options = {});

}  // namespace exoid::ident
