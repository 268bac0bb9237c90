#pragma once
// Is an estimate further from the physically consistent set than its noise explains? The distance
// D from the estimate to its nearest consistent estimate (found in the fit's metric), measured in
// the estimate's covariance, is compared with the distances of estimates drawn about a consistent
// centre (a parametric bootstrap, N(centre, covariance)), each refitted as the estimate was.
//
// Why draws: with one bound active and the covariance the fit's metric, D is half-normal beyond 0
// and the test is "D > s"; with k bounds active at once (a URDF's zero friction, a thin link) D^2
// grows like a chi-square of up to k degrees of freedom, and a fit whose metric is not its
// covariance's (least squares with Newey-West errors) stretches D by a factor of its own. The draws
// measure both, whatever k and the set's shape.
//
// The centre is the nearest consistent estimate with each friction or armature coefficient that is
// a base parameter of its own (not one regrouped with a link's inertia) and that it holds within
// bound_selection_sigmas of 0 put on 0: where the truth sits on such a bound and noise
// stepped the estimate off it, draws about the estimate would see that bound active half as often
// as the truth's records do (the bootstrap at a boundary; Andrews and Soares' moment selection).
//
// D <= s is never significant, and is not drawn: the centre lies on the consistent set's boundary,
// so the set lies inside a half-space through it, and a draw is at least as far from the set as
// from that half-space, a half-normal distance.
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
  /// Draws about the centre. Range >= 19. Default 199 (p in steps of 0.005).
  int draws = 199;
  /// A friction or armature coefficient (a base parameter of its own) the nearest consistent
  /// estimate holds within this many standard errors of 0 is put on 0 in the centre. Range >= 0 (0:
  /// the nearest consistent estimate itself). Default 3, about Andrews and Soares' sqrt(ln n) (3.0
  /// to 3.4 for 8,000 to 100,000 rows, though a record's rows are not independent).
  double bound_selection_sigmas = 3.0;
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
  /// draws' p-value would not fall below (1 for a consistent estimate)
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
