#include "exoid/ident/estimators/standard_errors.hpp"

#include "exoid/core/format.hpp"

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace exoid::ident {

int neweyWestLags(Eigen::Index n) {
  return std::max(1, static_cast<int>(std::floor(4.0 * std::pow(static_cast<double>(n) / 100.0, 2.0 / 9.0))));
}

std::vector<Channel> interleavedChannels(Eigen::Index rows, int equations) {
  if (equations < 1) throw std::invalid_argument("interleavedChannels: equations must be >= 1");
  std::vector<Channel> out(static_cast<std::size_t>(equations));
  for (Eigen::Index i = 0; i < rows; ++i) out[static_cast<std::size_t>(i % equations)].push_back(i);
  return out;
}

Eigen::MatrixXd residualCovariance(const Eigen::MatrixXd& H, const Eigen::VectorXd& residual,
                                   const std::vector<Channel>& channels, int lags, int rows_per_step) {
  if (rows_per_step < 1) throw std::invalid_argument("residual covariance: rows_per_step must be >= 1");
  const Eigen::Index p = H.cols();
  if (residual.size() != H.rows()) {
    throw std::invalid_argument("residual covariance: " + core::toText(H.rows()) + " rows but " +
                                core::toText(residual.size()) + " residuals");
  }
  std::size_t longest = 0;
  for (const Channel& c : channels) {
    longest = std::max(longest, c.size());
    for (Eigen::Index i : c) {
      if (i < 0 || i >= H.rows()) throw std::invalid_argument("residual covariance: row index " + core::toText(i) + " out of range");
    }
  }
  const int L = lags >= 0 ? lags : neweyWestLags(static_cast<Eigen::Index>(longest) / rows_per_step);
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(p, p);
  for (const Channel& c : channels) {
    const Eigen::Index rows = static_cast<Eigen::Index>(c.size());
    const Eigen::Index n = (rows + rows_per_step - 1) / rows_per_step;
    Eigen::MatrixXd u = Eigen::MatrixXd::Zero(n, p);  // sum over the step's rows of h r
    for (Eigen::Index k = 0; k < rows; ++k) {
      const Eigen::Index row = c[static_cast<std::size_t>(k)];
      u.row(k / rows_per_step) += H.row(row) * residual[row];
    }
    S.noalias() += u.transpose() * u;
    for (int l = 1; l <= L && l < n; ++l) {
      const double w = 1.0 - static_cast<double>(l) / (L + 1.0);
      const Eigen::MatrixXd G = u.topRows(n - l).transpose() * u.bottomRows(n - l);
      S.noalias() += w * (G + G.transpose());
    }
  }
  // (H^T H)^-1 through the column-pivoted QR of H (no squaring of the condition number).
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(H);
  if (qr.rank() < p) return Eigen::MatrixXd::Constant(p, p, std::numeric_limits<double>::infinity());
  const Eigen::MatrixXd R = qr.matrixR().topLeftCorner(p, p).template triangularView<Eigen::Upper>();
  const Eigen::MatrixXd Rinv = R.template triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(p, p));
  const Eigen::MatrixXd A = qr.colsPermutation() * Rinv;  // (H^T H)^-1 = A A^T
  const Eigen::MatrixXd B = A * A.transpose();
  Eigen::MatrixXd C = B * S * B;
  return 0.5 * (C + C.transpose());
}

}  // namespace exoid::ident
