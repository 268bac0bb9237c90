#pragma once
// Physically consistent estimation for any serial chain: the base parameters closest to the data
// (least squares) among those of real bodies, every link's pseudo-inertia positive definite and
// every friction and armature coefficient non-negative. Searched in log-Cholesky coordinates
// (log_cholesky.hpp: consistent by construction) by Levenberg-Marquardt, fitted in
// base-parameter space: with beta_ls the LS estimate and A = Wb' Wb, the cost is
//   ||Wb beta - y||^2 = ||Wb beta_ls - y||^2 + (beta - beta_ls)' A (beta - beta_ls),  beta = C phi(theta),
// so an iteration costs O(parameters^2), whatever the log's length. The set of consistent beta is
// convex (a linear image of a convex cone) and the coordinates map onto it smoothly, so a local
// minimum is the global one. When LS is not consistent the optimum lies on the set's boundary,
// which the coordinates reach only at infinity: LM slows to a crawl there (measured: 0.1 % from
// the optimum after 20,000 iterations), so a log-barrier interior point in standard parameters
// (log det of each pseudo-inertia, a mass bound and a bounding sphere per link, which make the
// set compact) finishes from LM's point, to a duality-gap bound. The result is strictly
// consistent either way.
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/ident/model/chain.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace exoid::ident {

struct ConsistentFitOptions {
  /// Levenberg-Marquardt iterations at most. Range >= 1. Default 500.
  int max_iterations = 500;
  /// Stop when an accepted step lowers the excess cost (beta - beta_ls)' A (beta - beta_ls) by less
  /// than this fraction of beta_ls' A beta_ls, or the excess itself is below it. Range (0, 1e-3].
  /// Default 1e-20: a consistent LS estimate is met to ~1e-10 relative.
  double tolerance = 1e-20;
  /// When the optimum is on the boundary (LS not consistent), the barrier interior point that
  /// finishes the search stops when its bound on the excess cost's distance to the minimum is
  /// below this fraction of the residual sum of squares. Range (0, 1e-3]. Default 1e-6: the
  /// estimate is then within 1e-3 standard errors of the optimum (in the A = Wb' Wb metric).
  double barrier_gap = 1e-6;
  /// Every link's mass is at most this (kg). Not a physical prior: the bound only makes the
  /// optimum attained, where without it a mass that no torque shows would grow without bound
  /// towards a boundary optimum. Default 1e4, beyond any exoskeleton link; the estimate then
  /// differs from the unbounded infimum by about (first moment)^2 / max_link_mass_kg in the
  /// inertias that mass regroups with (4e-3 kg m^2 for a 13 kg thigh with its COM 0.45 m out).
  double max_link_mass_kg = 1e4;
  /// Every link's mass lies within a sphere of this radius (m) about its frame's origin
  /// (R^2 m >= tr Sigma: Wensing, Kim and Slotine's bounding volume). Default 2.
  double link_radius_m = 2.0;
  /// Newton steps of the barrier at most. Range >= 1. Default 400.
  int max_newton_steps = 400;
  void validate() const;  ///< throws std::invalid_argument naming the field
};

enum class ConsistentFitStatus {
  /// beta_ls itself is realised by consistent links: the excess cost within `tolerance` of the
  /// scale, or, when rounding or the budget stopped the barrier, within the gap bound it proved
  kLeastSquaresConsistent,
  kConstrained,             ///< the optimum lies on the consistent set's boundary
  kMaxIterations,           ///< stopped by max_iterations: the estimate is consistent, maybe not optimal
};
const char* toString(ConsistentFitStatus s);

struct ConsistentFit {
  Eigen::VectorXd phi;      ///< standard parameters: every link consistent, friction and armature >= 0
  Eigen::VectorXd beta;     ///< its base parameters (base.combination * phi)
  Eigen::VectorXd beta_ls;  ///< the unconstrained least-squares base parameters
  double excess_cost = 0.0;  ///< (beta - beta_ls)' A (beta - beta_ls): what consistency costs the fit
  double ls_cost = 0.0;      ///< ||Wb beta_ls - y||^2
  int iterations = 0;            ///< Levenberg-Marquardt iterations
  int barrier_newton_steps = 0;  ///< Newton steps of the barrier (0 when LS was consistent)
  ConsistentFitStatus status = ConsistentFitStatus::kMaxIterations;
  std::vector<double> link_min_eigenvalue;  ///< smallest eigenvalue of each link's pseudo-inertia (> 0)
  std::string message;
};

/// W: stacked standard regressor rows (N x model.standardParameterCount()), y: torques. phi_start:
/// where the search starts (e.g. the nominal parameters of the robot's file); links that are not
/// consistent there start as a 1 kg point-like body at their origin, frictions below 1e-6 at 1.
/// Throws std::invalid_argument on size mismatches, non-finite data, or base columns of W that
/// are not of full rank (the record does not identify the base parameters).
ConsistentFit consistentFit(const ChainModel& model, const BaseParameters& base, const Eigen::MatrixXd& W,
                            const Eigen::VectorXd& y, const Eigen::VectorXd& phi_start,
                            const ConsistentFitOptions& options = {});

/// The same from the normal equations of the base regressor: A = Wb' Wb (full rank) and
/// b = Wb' y, yy = y' y.
ConsistentFit consistentFitNormal(const ChainModel& model, const BaseParameters& base, const Eigen::MatrixXd& A,
                                  const Eigen::VectorXd& b, double yy, const Eigen::VectorXd& phi_start,
                                  const ConsistentFitOptions& options = {});

}  // namespace exoid::ident
