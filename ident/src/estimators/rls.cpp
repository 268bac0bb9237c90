#include "exoid/ident/estimators/rls.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/estimators/stopwatch.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace exoid::ident {

void RlsOptions::validate() const {
  if (!(forgetting > 0.0 && forgetting <= 1.0)) {
    throw std::invalid_argument("'forgetting' must be in (0, 1], got " + core::toText(forgetting));
  }
  if (!(initial_covariance > 0.0 && std::isfinite(initial_covariance))) {
    throw std::invalid_argument("'initial_covariance' must be finite and > 0, got " +
                                core::toText(initial_covariance));
  }
}

RecursiveLeastSquares::RecursiveLeastSquares(Eigen::Index p, const RlsOptions& options,
                                             const Eigen::VectorXd& initial_estimate)
    : options_(options) {
  options_.validate();
  if (p <= 0) throw std::invalid_argument("RLS: parameter count must be > 0, got " + core::toText(p));
  if (initial_estimate.size() != 0 && initial_estimate.size() != p) {
    throw std::invalid_argument("RLS: initial estimate has " + core::toText(initial_estimate.size()) +
                                " entries, expected " + core::toText(p));
  }
  x_ = initial_estimate.size() ? initial_estimate : Eigen::VectorXd::Zero(p);
  P_ = Eigen::MatrixXd::Identity(p, p) * options_.initial_covariance;
  Ph_.resize(p);
  history_.resize(p, 0);
}

void RecursiveLeastSquares::reserveHistory(Eigen::Index updates) {
  if (!options_.keep_history) return;
  Eigen::MatrixXd h(x_.size(), updates);
  h.leftCols(stored_) = history_.leftCols(stored_);
  history_.swap(h);
}

void RecursiveLeastSquares::record() {
  ++count_;
  if (!options_.keep_history) return;
  if (stored_ == history_.cols()) reserveHistory(std::max<Eigen::Index>(64, 2 * stored_));
  history_.col(stored_++) = x_;
}

void RecursiveLeastSquares::correct(const Eigen::Ref<const Eigen::RowVectorXd>& h, double y, double lambda) {
  Ph_.noalias() = P_ * h.transpose();
  const double denom = h.dot(Ph_) + lambda;  // h^T P h + lambda > 0 while P is positive definite
  const double innovation = y - h.dot(x_);
  x_.noalias() += Ph_ * (innovation / denom);
  // P = (P - P h h^T P / denom) / lambda
  P_.noalias() -= (Ph_ / denom) * Ph_.transpose();
  if (lambda != 1.0) P_ /= lambda;
}

void RecursiveLeastSquares::update(const Eigen::Ref<const Eigen::RowVectorXd>& h, double y) {
  correct(h, y, options_.forgetting);
  record();
}

void RecursiveLeastSquares::update(const Eigen::Ref<const Eigen::Matrix<double, 2, Eigen::Dynamic>>& H,
                                   const Eigen::Vector2d& y) {
  // The 2-output update (P^-1 <- lambda P^-1 + H^T H) done as two scalar corrections, the
  // forgetting applied once. Algebraically the block form; numerically it avoids inverting
  // H P H^T, whose cancellation costs ~p0^2 eps instead of ~p0 eps with a large P0.
  correct(H.row(0), y[0], options_.forgetting);
  correct(H.row(1), y[1], 1.0);
  record();
}

RlsResult runRls(const Eigen::MatrixXd& H, const Eigen::VectorXd& y, const RlsOptions& options) {
  if (H.rows() != y.size() || H.rows() == 0) {
    throw std::invalid_argument("RLS: regressor has " + core::toText(H.rows()) +
                                " rows and the torque vector " + core::toText(y.size()));
  }
  if (!H.allFinite() || !y.allFinite()) throw std::invalid_argument("RLS: input contains NaN or Inf");
  Stopwatch clock;
  RecursiveLeastSquares rls(H.cols(), options);
  rls.reserveHistory(H.rows());
  for (Eigen::Index i = 0; i < H.rows(); ++i) rls.update(H.row(i), y[i]);
  RlsResult r;
  r.x = rls.estimate();
  r.history = rls.history();
  r.summary.iterations = H.rows();
  r.summary.final_cost = (y - H * r.x).cwiseAbs().sum();
  r.summary.initial_cost = y.cwiseAbs().sum();
  if (r.x.allFinite()) {
    r.summary.status = Status::kConverged;
    r.summary.message = "processed " + core::toText(H.rows()) + " samples";
  } else {
    r.summary.status = Status::kFailed;
    r.summary.message = "estimate became non-finite";
    r.x.setZero();
  }
  r.summary.wall_time_s = clock.seconds();
  return r;
}

void FluctuationOptions::validate() const {
  if (!(burn_in_fraction >= 0.0 && burn_in_fraction < 1.0)) {
    throw std::invalid_argument("'burn_in_fraction' must be in [0, 1), got " +
                                core::toText(burn_in_fraction));
  }
  if (!(margin_fraction >= 0.0 && std::isfinite(margin_fraction))) {
    throw std::invalid_argument("'margin_fraction' must be >= 0, got " + core::toText(margin_fraction));
  }
  if (!(min_width > 0.0 && std::isfinite(min_width))) {
    throw std::invalid_argument("'min_width' must be > 0, got " + core::toText(min_width));
  }
}

Box fluctuationRange(const Eigen::Ref<const Eigen::MatrixXd>& history, const FluctuationOptions& o) {
  o.validate();
  const Eigen::Index n = history.cols();
  const auto first = static_cast<Eigen::Index>(std::floor(o.burn_in_fraction * static_cast<double>(n)));
  if (n == 0 || first >= n) {
    throw std::invalid_argument("fluctuation range: no estimates left after the burn-in (" +
                                core::toText(n) + " updates)");
  }
  const auto kept = history.rightCols(n - first);
  Box box{kept.rowwise().minCoeff(), kept.rowwise().maxCoeff()};
  const Eigen::VectorXd width = box.upper - box.lower;
  box.lower -= o.margin_fraction * width;
  box.upper += o.margin_fraction * width;
  for (Eigen::Index i = 0; i < box.dim(); ++i) {
    if (box.upper[i] - box.lower[i] < o.min_width) {
      const double c = 0.5 * (box.upper[i] + box.lower[i]);
      box.lower[i] = c - 0.5 * o.min_width;
      box.upper[i] = c + 0.5 * o.min_width;
    }
  }
  return box;
}

}  // namespace exoid::ident
