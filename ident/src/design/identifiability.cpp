#include "exoid/ident/design/identifiability.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/estimators/least_squares.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace exoid::ident {

namespace {

void checkReference(const Eigen::VectorXd& reference, Eigen::Index columns) {
  if (reference.size() != 0 && reference.size() != columns) {
    throw std::invalid_argument("identifiability: reference has " + core::toText(reference.size()) + " entries, expected " +
                                core::toText(columns));
  }
}

// The report from LS's own factor: (H^T H)^-1 = D (Hs^T Hs)^-1 D with Hs = H D column-scaled.
IdentifiabilityReport reportOf(const Eigen::MatrixXd& H, const LsResult& ls, double noise_sigma, const Eigen::VectorXd& reference) {
  const Eigen::Index p = H.cols();
  const double inf = std::numeric_limits<double>::infinity();
  IdentifiabilityReport r;
  r.rows = H.rows();
  r.rank = ls.rank;
  r.unidentifiable = ls.unidentifiable;
  r.condition_number = ls.rank < p ? inf : ls.condition_number;
  r.crb_std = Eigen::VectorXd::Constant(p, inf);
  r.crb_rel_std = Eigen::VectorXd::Constant(p, inf);
  r.collinearity_r2 = ls.collinearity_r2;
  if (ls.rank < p) return r;
  const Eigen::VectorXd d = columnScales(H);
  const Eigen::VectorXd& ref = reference.size() ? reference : ls.x;
  for (Eigen::Index j = 0; j < p; ++j) {
    r.crb_std[j] = noise_sigma * d[j] * std::sqrt(ls.variance_inflation[j]);
    r.crb_rel_std[j] = ref[j] != 0.0 ? r.crb_std[j] / std::abs(ref[j]) : inf;
  }
  return r;
}

}  // namespace

IdentifiabilityReport analyzeIdentifiability(const Eigen::MatrixXd& H, const Eigen::VectorXd& y,
                                             double noise_sigma, const Eigen::VectorXd& reference) {
  if (!(noise_sigma >= 0.0 && std::isfinite(noise_sigma))) {
    throw std::invalid_argument("noise sigma must be finite and >= 0 N m, got " + core::toText(noise_sigma));
  }
  checkReference(reference, H.cols());
  return reportOf(H, solveLeastSquares(H, y), noise_sigma, reference);
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
  checkReference(reference, H.cols());
  const LsResult ls = solveLeastSquares(H, y);
  IdentifiabilityReport r = reportOf(H, ls, 0.0, reference);
  if (r.rank < H.cols()) return r;
  const Eigen::VectorXd& ref = reference.size() ? reference : ls.x;
  r.crb_std = stdOf(lsNoiseCovariance(channels));
  for (Eigen::Index j = 0; j < H.cols(); ++j) {
    r.crb_rel_std[j] = ref[j] != 0.0 ? r.crb_std[j] / std::abs(ref[j]) : std::numeric_limits<double>::infinity();
  }
  return r;
}

}  // namespace exoid::ident
