#pragma once
// Is an estimate further from the physically consistent set than its noise explains? The distance
// D from the estimate to its nearest consistent estimate, in standard errors, is compared with the
// distances of estimates drawn about that nearest one (a parametric bootstrap: N(beta_c, covariance)),
// each refitted as the estimate was. With one constraint active D is half-normal beyond 0 and the
// test is "D > s"; with k active at once (a URDF's zero friction, a thin link) D^2 grows like a
// chi-square of up to k degrees of freedom, which the draws measure whatever k and the set's shape.
// D <= s is never significant: the consistent set lies inside a half-space through beta_c, so a
// draw is at least as far as its distance to that half-space, a half-normal variable.
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/ident/model/chain.hpp"
#include "exoid/ident/model/consistent_fit.hpp"

#include <Eigen/Core>

#include <cstdint>

namespace exoid::ident {

struct ConsistencyVerdictOptions {
  /// Significant when the draws put the estimate's distance beyond the one-sided normal tail of
  /// this many standard errors: p <= 1 - Phi(s). Range > 0. Default 2 (p <= 0.0228).
  double significance_sigmas = 2.0;
  /// Draws about the nearest consistent estimate. Range >= 19. Default 199 (p resolved to 0.005).
  int draws = 199;
  std::uint64_t seed = 1;  ///< draw i from sub-stream i of this seed (core::deriveSeed)
  int threads = 0;         ///< 0: every core; the verdict is the same bytes whatever the number
  ConsistentFitOptions fit;
  void validate() const;  ///< throws std::invalid_argument naming the field
};

struct ConsistencyVerdict {
  double distance = 0.0;  ///< standard errors from the estimate to its nearest consistent estimate
  double level = 0.0;     ///< 1 - Phi(significance_sigmas)
  int draws = 0;          ///< 0 when not drawn (distance <= significance_sigmas)
  int as_far = 0;         ///< draws at least `distance` from their own nearest consistent estimate
  /// (as_far + 1) / (draws + 1); when not drawn, the half-normal bound 1 - Phi(distance), which the
  /// draws' p-value would not fall below
  double p_value = 1.0;
  bool significant = false;
};

/// `nearest`: consistentFitNormal(model, base, metric, metric * theta, yy, phi_start, options.fit),
/// the nearest consistent estimate of theta in the fit's metric (A = Wb' Wb for least squares, the
/// inverse covariance for another method's estimate). Each draw is refitted the same way, from
/// phi_start, with the same residual sum of squares. Throws std::invalid_argument on sizes that
/// disagree or a covariance that is not positive definite.
ConsistencyVerdict judgeConsistency(const ChainModel& model, const BaseParameters& base, const Eigen::VectorXd& theta,
                                    const ConsistentFit& nearest, const Eigen::MatrixXd& metric, const Eigen::MatrixXd& covariance,
                                    const Eigen::VectorXd& phi_start, const ConsistencyVerdictOptions& options = {});

}  // namespace exoid::ident
