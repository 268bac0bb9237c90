#include "exoid/ident/design/identifiability.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/estimators/least_squares.hpp"

#include <Eigen/QR>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace exoid::ident {

IdentifiabilityReport analyzeIdentifiability(const Eigen::MatrixXd& H, const Eigen::VectorXd& y,
                                             double noise_sigma, const Eigen::VectorXd& reference) {
  if (!(noise_sigma >= 0.0 && std::isfinite(noise_sigma))) {
    throw std::invalid_argument("noise sigma must be finite and >= 0 N m, got " + core::toText(noise_sigma));
  }
  if (reference.size() != 0 && reference.size() != H.cols()) {
    throw std::invalid_argument("identifiability: reference has " + core::toText(reference.size()) +
                                " entries, expected " + core::toText(H.cols()));
  }
  const LsResult ls = solveLeastSquares(H, y);
  const Eigen::Index p = H.cols();
  IdentifiabilityReport r;
  r.rows = H.rows();
  r.rank = ls.rank;
  r.unidentifiable = ls.unidentifiable;
  r.condition_number = ls.rank < p ? std::numeric_limits<double>::infinity() : ls.condition_number;
  const double inf = std::numeric_limits<double>::infinity();
  r.crb_std = Eigen::VectorXd::Constant(p, inf);
  r.crb_rel_std = Eigen::VectorXd::Constant(p, inf);
  r.collinearity_r2 = Eigen::VectorXd::Ones(p);
  if (ls.rank < p) return r;

  // (H^T H)^-1 = D (Hs^T Hs)^-1 D with Hs = H D column-scaled; from Hs's R factor.
  const Eigen::VectorXd d = columnScales(H);
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(H * d.asDiagonal());
  const Eigen::MatrixXd R = qr.matrixQR().topRows(p).template triangularView<Eigen::Upper>();
  const Eigen::MatrixXd Rinv =
      R.template triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(p, p));
  const Eigen::VectorXd diag_scaled = Rinv.rowwise().squaredNorm();  // diag((Hs^T Hs)^-1)
  const Eigen::VectorXd& ref = reference.size() ? reference : ls.x;
  for (Eigen::Index j = 0; j < p; ++j) {
    r.crb_std[j] = noise_sigma * d[j] * std::sqrt(diag_scaled[j]);
    r.crb_rel_std[j] = ref[j] != 0.0 ? r.crb_std[j] / std::abs(ref[j]) : inf;
    // Scaled columns have unit norm, so ||h_j||^2 [(H^T H)^-1]_jj = diag_scaled[j].
    r.collinearity_r2[j] = 1.0 - 1.0 / diag_scaled[j];
  }
  return r;
}

IdentifiabilityReport analyzeIdentifiability(const std::vector<NoiseChannel>& channels, const Eigen::VectorXd& y,
                                             const Eigen::VectorXd& reference) {
  if (channels.empty()) throw std::invalid_argument("identifiability: no noise channels");
  Eigen::Index rows = 0;
  for (const NoiseChannel& c : channels) rows += c.H.rows();
  Eigen::MatrixXd H(rows, channels.front().H.cols());
  rows = 0;
  for (const NoiseChannel& c : channels) {
    if (c.H.cols() != H.cols()) throw std::invalid_argument("identifiability: noise channels differ in column count");
    H.middleRows(rows, c.H.rows()) = c.H;
    rows += c.H.rows();
  }
  IdentifiabilityReport r = analyzeIdentifiability(H, y, 0.0, reference);
  if (r.rank < H.cols()) return r;
  const Eigen::VectorXd& ref = reference.size() ? reference : solveLeastSquares(H, y).x;
  r.crb_std = stdOf(lsNoiseCovariance(channels));
  for (Eigen::Index j = 0; j < H.cols(); ++j) {
    r.crb_rel_std[j] = ref[j] != 0.0 ? r.crb_std[j] / std::abs(ref[j]) : std::numeric_limits<double>::infinity();
  }
  return r;
}

}  // namespace exoid::ident
