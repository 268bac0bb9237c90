#include "exoid/ident/estimators/least_squares.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/estimators/stopwatch.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>

#include <limits>
#include <stdexcept>
#include <string>

namespace exoid::ident {

void LsOptions::validate() const {
  if (!(max_condition > 1.0)) {
    throw std::invalid_argument("'max_condition' must be > 1, got " + core::toText(max_condition));
  }
  if (!(rank_tolerance > 0.0 && rank_tolerance < 1.0)) {
    throw std::invalid_argument("'rank_tolerance' must be in (0, 1), got " +
                                core::toText(rank_tolerance));
  }
}

std::string illConditionedMessage(double condition, double max_condition) {
  return "ill-conditioned: condition number " + core::formatNumber(condition, 4) + " of the column-scaled regressor > " +
         core::formatNumber(max_condition, 4) + " (max_condition): a relative torque error of 1/" +
         core::formatNumber(max_condition, 4) + " can move the estimate by 100 %; `exoid identifiability` says which "
         "motion would separate the parameters";
}

namespace {
// Ratio of the extreme singular values of the p x p triangular factor of a QR: those of the
// matrix it factors (infinity when singular).
double conditionOfFactor(const Eigen::MatrixXd& R) {
  const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(R).singularValues();
  return sv[sv.size() - 1] > 0.0 ? sv[0] / sv[sv.size() - 1] : std::numeric_limits<double>::infinity();
}
}  // namespace

double scaledConditionNumber(const Eigen::MatrixXd& H) {
  const Eigen::Index p = H.cols();
  if (p == 0 || H.rows() < p) {
    throw std::invalid_argument("condition number: need at least as many rows as columns, got " + core::toText(H.rows()) +
                                " x " + core::toText(p));
  }
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(H * columnScales(H).asDiagonal());
  return conditionOfFactor(qr.matrixQR().topRows(p).template triangularView<Eigen::Upper>());
}

Eigen::VectorXd columnScales(const Eigen::MatrixXd& H) {
  Eigen::VectorXd s(H.cols());
  for (Eigen::Index j = 0; j < H.cols(); ++j) {
    const double n = H.col(j).norm();
    s[j] = n > 0.0 ? 1.0 / n : 1.0;
  }
  return s;
}

LsResult solveLeastSquares(const Eigen::MatrixXd& H, const Eigen::VectorXd& y,
                           const LsOptions& options) {
  options.validate();
  if (H.rows() != y.size()) {
    throw std::invalid_argument("least squares: regressor has " + core::toText(H.rows()) +
                                " rows but the torque vector has " + core::toText(y.size()));
  }
  if (H.cols() == 0 || H.rows() < H.cols()) {
    throw std::invalid_argument("least squares: need at least as many rows as parameters, got " +
                                core::toText(H.rows()) + " x " + core::toText(H.cols()));
  }
  if (!H.allFinite() || !y.allFinite()) {
    throw std::invalid_argument("least squares: regressor or torque contains NaN or Inf");
  }
  Stopwatch clock;
  const Eigen::VectorXd scale = columnScales(H);
  const Eigen::MatrixXd Hs = H * scale.asDiagonal();
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Hs);
  qr.setThreshold(options.rank_tolerance);
  LsResult r;
  r.rank = qr.rank();
  const Eigen::Index p = H.cols();
  r.condition_number = conditionOfFactor(qr.matrixR().topLeftCorner(p, p).template triangularView<Eigen::Upper>());
  r.collinearity_r2 = Eigen::VectorXd::Ones(p);
  r.variance_inflation = Eigen::VectorXd::Constant(p, std::numeric_limits<double>::infinity());
  if (r.rank == p) {
    // (Hs^T Hs)^-1 = P R^-1 R^-T P^T from the factor itself (p x p work).
    const Eigen::MatrixXd R = qr.matrixR().topLeftCorner(p, p).template triangularView<Eigen::Upper>();
    const Eigen::MatrixXd Rinv = R.template triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(p, p));
    const Eigen::MatrixXd PRinv = qr.colsPermutation() * Rinv;
    r.variance_inflation = PRinv.rowwise().squaredNorm();
    r.collinearity_r2 = (1.0 - r.variance_inflation.array().inverse()).matrix();
  }
  r.x = scale.asDiagonal() * qr.solve(y);
  const Eigen::VectorXd res = y - H * r.x;
  r.residual_rms = std::sqrt(res.squaredNorm() / static_cast<double>(res.size()));
  r.summary.iterations = 1;
  r.summary.final_cost = res.squaredNorm();
  r.summary.initial_cost = y.squaredNorm();
  if (r.rank < p) {
    std::string names;
    for (Eigen::Index k = r.rank; k < p; ++k) {
      const Eigen::Index col = qr.colsPermutation().indices()[k];
      r.unidentifiable.push_back(col);
      names += (names.empty() ? "" : ", ") + core::toText(col);
    }
    r.summary.status = Status::kRankDeficient;
    r.summary.message = "rank " + core::toText(r.rank) + " < " + core::toText(p) +
                        ": columns {" + names + "} cannot be separated from the others";
  } else {
    r.summary.status = Status::kConverged;
    r.summary.message = "full rank";
    if (r.condition_number > options.max_condition) {
      r.summary.status = Status::kIllConditioned;
      r.summary.message = illConditionedMessage(r.condition_number, options.max_condition);
    }
  }
  r.summary.wall_time_s = clock.seconds();
  return r;
}

}  // namespace exoid::ident
