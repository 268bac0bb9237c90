#include "exoid/ident/estimators/standard_errors.hpp"

#include "exoid/core/format.hpp"

#include <Eigen/Cholesky>
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

std::vector<RowBlock> recordBlocks(const std::vector<Eigen::Index>& record_rows, Eigen::Index total_rows, int rows_per_step, int blocks) {
  if (rows_per_step < 1) throw std::invalid_argument("record blocks: rows_per_step must be >= 1");
  const std::vector<Eigen::Index> records = record_rows.empty() ? std::vector<Eigen::Index>{total_rows} : record_rows;
  Eigen::Index sum = 0;
  for (Eigen::Index r : records) sum += r;
  if (sum != total_rows) throw std::invalid_argument("record blocks: records of " + core::toText(sum) + " rows, the problem has " + core::toText(total_rows));
  const auto per_record = static_cast<Eigen::Index>(std::max<std::size_t>(2, (static_cast<std::size_t>(std::max(blocks, 1)) + records.size() - 1) / records.size()));
  std::vector<RowBlock> out;
  Eigen::Index start = 0;
  for (Eigen::Index rows : records) {
    const Eigen::Index steps = rows / rows_per_step;
    for (Eigen::Index b = 0; b < per_record; ++b) {
      const Eigen::Index from = start + steps * b / per_record * rows_per_step;
      const Eigen::Index to = b + 1 == per_record ? start + rows : start + steps * (b + 1) / per_record * rows_per_step;
      if (to > from) out.push_back({from, to - from});
    }
    start += rows;
  }
  return out;
}

std::vector<RowBlock> wholeRecords(const std::vector<Eigen::Index>& record_rows, Eigen::Index total_rows) {
  std::vector<RowBlock> out;
  Eigen::Index start = 0;
  for (Eigen::Index rows : record_rows.empty() ? std::vector<Eigen::Index>{total_rows} : record_rows) {
    out.push_back({start, rows});
    start += rows;
  }
  if (start != total_rows) throw std::invalid_argument("whole records: records of " + core::toText(start) + " rows, the problem has " + core::toText(total_rows));
  return out;
}

Eigen::MatrixXd blockJackknifeCovariance(const Eigen::MatrixXd& H, const Eigen::VectorXd& y, const std::vector<RowBlock>& blocks) {
  const Eigen::Index p = H.cols();
  const auto G = static_cast<Eigen::Index>(blocks.size());
  if (G < 2) return Eigen::MatrixXd::Constant(p, p, std::numeric_limits<double>::quiet_NaN());
  // Unit columns: the normal equations' condition is the scaled regressor's squared.
  Eigen::VectorXd scale = H.colwise().norm().transpose();
  for (Eigen::Index c = 0; c < p; ++c) scale[c] = scale[c] > 0.0 ? scale[c] : 1.0;
  const Eigen::MatrixXd Hs = H * scale.cwiseInverse().asDiagonal();
  const Eigen::MatrixXd A = Hs.transpose() * Hs;
  const Eigen::VectorXd b = Hs.transpose() * y;
  Eigen::MatrixXd fits(G, p);
  for (Eigen::Index g = 0; g < G; ++g) {
    const RowBlock& k = blocks[static_cast<std::size_t>(g)];
    if (k.first < 0 || k.rows < 0 || k.first + k.rows > H.rows()) throw std::invalid_argument("block jackknife: a block outside the rows");
    const auto Hg = Hs.middleRows(k.first, k.rows);
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(A - Hg.transpose() * Hg);
    // A pivot at rounding level of the unit diagonal: the fit without this block is singular (LDLT
    // would quietly solve the rest).
    const Eigen::VectorXd d = ldlt.vectorD();
    if (ldlt.info() != Eigen::Success || !(d.minCoeff() > 1e-14 * d.cwiseAbs().maxCoeff())) {
      return Eigen::MatrixXd::Constant(p, p, std::numeric_limits<double>::infinity());
    }
    fits.row(g) = ldlt.solve(b - Hg.transpose() * y.segment(k.first, k.rows)).transpose();
  }
  const Eigen::MatrixXd centred = fits.rowwise() - fits.colwise().mean();
  const Eigen::MatrixXd V = (static_cast<double>(G - 1) / static_cast<double>(G)) * (centred.transpose() * centred);
  return scale.cwiseInverse().asDiagonal() * V * scale.cwiseInverse().asDiagonal();
}

ReportedErrors combineReportedErrors(const Eigen::MatrixXd& newey_west, const Eigen::MatrixXd& block_jackknife,
                                     const std::optional<Eigen::MatrixXd>& record_jackknife) {
  const Eigen::Index p = newey_west.rows();
  ReportedErrors out;
  const auto sd = [](const Eigen::MatrixXd& c) { return Eigen::VectorXd(c.diagonal().cwiseMax(0.0).cwiseSqrt()); };
  out.newey_west = sd(newey_west);
  out.block_jackknife = sd(block_jackknife);
  // Between records: a variance with 2 degrees of freedom or more.
  out.record_jackknife = record_jackknife ? sd(*record_jackknife) : Eigen::VectorXd::Constant(p, std::numeric_limits<double>::quiet_NaN());
  out.jackknife = out.block_jackknife;
  for (Eigen::Index i = 0; i < p; ++i) {
    if (out.record_jackknife[i] > out.jackknife[i] || std::isnan(out.jackknife[i])) out.jackknife[i] = out.record_jackknife[i];
  }
  out.reported = out.newey_west;
  out.from_jackknife.assign(static_cast<std::size_t>(p), false);
  Eigen::VectorXd raise = Eigen::VectorXd::Ones(p);
  for (Eigen::Index i = 0; i < p; ++i) {
    if (!(out.jackknife[i] > out.newey_west[i])) continue;  // NaN (too few blocks) keeps Newey-West's
    out.reported[i] = out.jackknife[i];
    out.from_jackknife[static_cast<std::size_t>(i)] = true;
    raise[i] = out.newey_west[i] > 0.0 ? out.jackknife[i] / out.newey_west[i] : 0.0;
  }
  out.covariance = raise.asDiagonal() * newey_west * raise.asDiagonal();
  // A parameter Newey-West puts no error on (an exact fit) takes the jackknife's alone.
  for (Eigen::Index i = 0; i < p; ++i) {
    if (raise[i] == 0.0) out.covariance(i, i) = out.reported[i] * out.reported[i];
  }
  return out;
}

ReportedErrors reportedErrors(const Eigen::MatrixXd& H, const Eigen::VectorXd& y, const Eigen::VectorXd& x, const std::vector<Channel>& channels,
                              int rows_per_step, const std::vector<RowBlock>& blocks, const std::vector<RowBlock>& records) {
  return combineReportedErrors(residualCovariance(H, y - H * x, channels, -1, rows_per_step), blockJackknifeCovariance(H, y, blocks),
                               records.size() >= 3 ? std::optional<Eigen::MatrixXd>(blockJackknifeCovariance(H, y, records)) : std::nullopt);
}

}  // namespace exoid::ident
