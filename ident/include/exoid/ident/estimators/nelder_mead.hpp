#pragma once
// Nelder-Mead simplex minimisation with the dimension-adaptive coefficients of Gao and Han (2012,
// Comput. Optim. Appl. 51:259): derivative-free, for small smooth-ish problems such as excitation
// design, where the objective (a condition number under penalties) has no useful gradient.
#include <Eigen/Core>

#include <functional>

namespace exoid::ident {

struct NelderMeadOptions {
  double initial_step = 0.05;   ///< simplex edge along each axis, > 0
  long max_evaluations = 5000;  ///< >= 1
  /// Stop when the simplex's function values span less than this (absolute), >= 0.
  double f_tolerance = 1e-10;
  /// ... and its vertices lie within this of the best (max norm), >= 0.
  double x_tolerance = 1e-10;
  void validate() const;  ///< throws std::invalid_argument naming the field
};

struct NelderMeadResult {
  Eigen::VectorXd x;
  double f = 0.0;
  long evaluations = 0;
  bool converged = false;  ///< met both tolerances before max_evaluations
};

/// Minimises f from x0. Deterministic. Non-finite values of f count as +infinity.
NelderMeadResult minimizeNelderMead(const std::function<double(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x0,
                                    const NelderMeadOptions& options = {});

}  // namespace exoid::ident
