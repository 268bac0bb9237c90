#include "exoid/ident/model/consistency_verdict.hpp"

#include "exoid/core/format.hpp"
#include "exoid/core/normal_tail.hpp"
#include "exoid/core/parallel_for.hpp"
#include "exoid/core/random.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace exoid::ident {

namespace {

// Standard errors from beta to its nearest consistent estimate `fit` (0 when beta is consistent).
double distanceOf(const ConsistentFit& fit, const Eigen::VectorXd& beta, const Eigen::LLT<Eigen::MatrixXd>& covariance) {
  if (fit.status == ConsistentFitStatus::kLeastSquaresConsistent) return 0.0;
  const Eigen::VectorXd d = fit.beta - beta;
  return std::sqrt(std::max(0.0, d.dot(covariance.solve(d))));
}

// The draws' centre (the header says why): beta_c with each friction or armature coefficient that is
// a base parameter of its own, c phi_k with c > 0, put on 0 when beta_c holds it within `sigmas`
// standard errors. Still consistent and on the boundary: only such coefficients move, to their bound.
Eigen::VectorXd drawCentre(const ChainModel& model, const BaseParameters& base, const Eigen::VectorXd& beta_c, const Eigen::VectorXd& se,
                           double sigmas) {
  std::vector<int> scalar;
  for (const JointParameterLayout& l : model.layout()) {
    if (l.friction >= 0) scalar.insert(scalar.end(), {l.friction, l.friction + 1});
    if (l.armature >= 0) scalar.push_back(l.armature);
  }
  Eigen::VectorXd centre = beta_c;
  for (Eigen::Index i = 0; i < base.rank; ++i) {
    const auto row = base.combination.row(i);
    for (int k : scalar) {
      // The base parameter is c phi_k alone (c > 0): its bound is beta_i >= 0.
      const bool alone = row[k] > 0.0 && row.cwiseAbs().sum() <= row[k] * (1.0 + 1e-12);
      if (alone && beta_c[i] < sigmas * se[i]) centre[i] = 0.0;
    }
  }
  return centre;
}

}  // namespace

void ConsistencyVerdictOptions::validate() const {
  if (!(significance_sigmas > 0.0) || !std::isfinite(significance_sigmas)) {
    throw std::invalid_argument("consistency verdict: significance_sigmas must be a positive number, got " + core::formatNumber(significance_sigmas));
  }
  if (draws < 19) throw std::invalid_argument("consistency verdict: draws must be >= 19, got " + core::toText(draws));
  if (!(bound_selection_sigmas >= 0.0) || !std::isfinite(bound_selection_sigmas)) {
    throw std::invalid_argument("consistency verdict: bound_selection_sigmas must be >= 0, got " + core::formatNumber(bound_selection_sigmas));
  }
  if (threads < 0) throw std::invalid_argument("consistency verdict: threads must be >= 0, got " + core::toText(threads));
  fit.validate();
}

ConsistencyVerdict judgeConsistency(const ChainModel& model, const BaseParameters& base, const Eigen::VectorXd& theta,
                                    const ConsistentFit& nearest, const Eigen::MatrixXd& metric, const Eigen::MatrixXd& covariance,
                                    const Eigen::VectorXd& phi_start, const ConsistencyVerdictOptions& options) {
  options.validate();
  const Eigen::Index n = theta.size();
  if (n != base.rank || metric.rows() != n || metric.cols() != n || covariance.rows() != n || covariance.cols() != n ||
      nearest.beta.size() != n) {
    throw std::invalid_argument("consistency verdict: expected " + core::toText(base.rank) + " base parameters, their metric and covariance");
  }
  const Eigen::LLT<Eigen::MatrixXd> cov(covariance);
  if (!covariance.allFinite() || cov.info() != Eigen::Success) {
    throw std::invalid_argument("consistency verdict: the covariance is not positive definite");
  }
  ConsistencyVerdict v;
  v.level = core::normalUpperTail(options.significance_sigmas);
  v.distance = distanceOf(nearest, theta, cov);
  v.p_value = v.distance > 0.0 ? core::normalUpperTail(v.distance) : 1.0;
  if (v.distance <= options.significance_sigmas) return v;

  // Each draw refits as theta was: the same metric, the same residual sum of squares beside it.
  const Eigen::MatrixXd L = cov.matrixL();
  const Eigen::VectorXd centre = drawCentre(model, base, nearest.beta, covariance.diagonal().cwiseSqrt(), options.bound_selection_sigmas);
  std::vector<char> as_far(static_cast<std::size_t>(options.draws), 0);
  // Each draw goes straight to the barrier (one Levenberg-Marquardt iteration): the problem is
  // convex, so the optimum is the same, and LM's crawl towards a boundary optimum is most of a
  // fit's time (docs/findings.md).
  ConsistentFitOptions fit_options = options.fit;
  fit_options.max_iterations = 1;
  core::parallelFor(as_far.size(), options.threads, [&](std::size_t i) {
    core::Rng rng(core::deriveSeed(options.seed, i));
    Eigen::VectorXd z(n);
    for (Eigen::Index k = 0; k < n; ++k) z[k] = rng.normal();
    const Eigen::VectorXd beta = centre + L * z;
    const Eigen::VectorXd b = metric * beta;
    const ConsistentFit fit = consistentFitNormal(model, base, metric, b, beta.dot(b) + nearest.ls_cost, phi_start, fit_options);
    as_far[i] = distanceOf(fit, beta, cov) >= v.distance;
  });
  v.draws = options.draws;
  for (char f : as_far) v.as_far += f;
  v.p_value = (v.as_far + 1.0) / (v.draws + 1.0);
  v.significant = v.p_value <= v.level;
  return v;
}

}  // namespace exoid::ident
