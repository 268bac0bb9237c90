#include "exoid/ident/estimators/noise_covariance.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/estimators/least_squares.hpp"

#include <Eigen/QR>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace exoid::ident {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kRankTolerance = LsOptions{}.rank_tolerance;

// Samples after which the one-pass impulse response has fallen below 1e-14 of its peak: the
// zero tail the backward pass needs so that starting it from rest truncates nothing.
Eigen::Index settlingSamples(const SosFilter& f) {
  for (Eigen::Index n = 1024;; n *= 2) {
    Eigen::MatrixXd impulse = Eigen::MatrixXd::Zero(n, 1);
    impulse(0, 0) = 1.0;
    const Eigen::VectorXd h = sosfilt(f, impulse).col(0).cwiseAbs();
    const double floor = 1e-14 * h.maxCoeff();
    Eigen::Index last = n - 1;
    while (last > 0 && h[last] <= floor) --last;
    if (last < n / 2 || n >= (Eigen::Index{1} << 24)) return last + 1;
  }
}

// The column-scaled pivoted QR of the stacked regressor and (Hs^T Hs)^-1, or nothing when rank
// deficient.
struct ScaledInverse {
  Eigen::VectorXd scale;     ///< D: Hs = H D
  Eigen::MatrixXd inverse;   ///< (Hs^T Hs)^-1
  bool full_rank = false;
};

ScaledInverse scaledInverse(const Eigen::MatrixXd& H) {
  ScaledInverse s;
  s.scale = columnScales(H);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(H * s.scale.asDiagonal());
  qr.setThreshold(kRankTolerance);
  const Eigen::Index p = H.cols();
  if (qr.rank() < p) return s;
  const Eigen::MatrixXd R = qr.matrixR().topLeftCorner(p, p).triangularView<Eigen::Upper>();
  const Eigen::MatrixXd Rinv = R.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(p, p));
  // Hs P = Q R, so (Hs^T Hs)^-1 = P R^-1 R^-T P^T.
  const Eigen::MatrixXd RRt = Rinv * Rinv.transpose();
  s.inverse = qr.colsPermutation() * RRt * qr.colsPermutation().transpose();
  s.full_rank = true;
  return s;
}

void checkChannel(const NoiseChannel& c, Eigen::Index p, std::size_t k) {
  const std::string where = "noise channel " + core::toText(k) + ": ";
  if (c.H.cols() != p) {
    throw std::invalid_argument(where + "expected " + core::toText(p) + " columns, got " + core::toText(c.H.cols()));
  }
  if (c.path.trim < 0 || c.H.rows() != c.path.fittedRows()) {
    throw std::invalid_argument(where + "expected " + core::toText(c.path.fittedRows()) + " rows (raw " +
                                core::toText(c.path.raw_rows) + " less 2 x trim " + core::toText(c.path.trim) +
                                "), got " + core::toText(c.H.rows()));
  }
  if (!(c.sigma_Nm >= 0.0 && std::isfinite(c.sigma_Nm))) {
    throw std::invalid_argument(where + "sigma must be finite and >= 0 N m");
  }
}

}  // namespace

Eigen::MatrixXd TorqueNoisePath::transposeApply(const Eigen::MatrixXd& H) const {
  if (H.rows() != fittedRows() || trim < 0 || decimation < 1) {
    throw std::invalid_argument("noise path: expected " + core::toText(fittedRows()) + " rows, got " +
                                core::toText(H.rows()));
  }
  // Decimation and trim transposed: each fitted row back at its raw sample, zeros elsewhere.
  Eigen::MatrixXd placed = Eigen::MatrixXd::Zero(raw_rows, H.cols());
  for (Eigen::Index i = 0; i < H.rows(); ++i) placed.row(trim + i * decimation) = H.row(i);
  if (!filter) return placed;
  // K z with K the symmetric kernel of filtfilt: causal pass from rest, then the anti-causal
  // pass from rest after a zero tail long enough for the causal output to have died out.
  const Eigen::Index tail = settlingSamples(*filter);
  Eigen::MatrixXd z = Eigen::MatrixXd::Zero(raw_rows + tail, H.cols());
  z.topRows(raw_rows) = placed;
  Eigen::MatrixXd y = sosfilt(*filter, z).colwise().reverse();
  y = sosfilt(*filter, y).colwise().reverse();
  return y.topRows(raw_rows);
}

TorqueNoisePath torqueNoisePath(const SignalOptions& o, double sample_rate_hz, Eigen::Index raw_rows) {
  o.validate();
  TorqueNoisePath p;
  p.raw_rows = raw_rows;
  p.trim = o.edgeTrimSamples(sample_rate_hz);
  const bool parallel = o.processing == Processing::kParallel;
  if (o.filter && (parallel || o.filter_torque)) p.filter = butterworthLowpass(o.filter_order, o.cutoff_hz, sample_rate_hz);
  if (parallel) p.decimation = o.decimationFactor(sample_rate_hz);
  return p;
}

TorqueNoisePath rawTorquePath(Eigen::Index raw_rows, Eigen::Index trim) {
  TorqueNoisePath p;
  p.raw_rows = raw_rows;
  p.trim = trim;
  return p;
}

Eigen::MatrixXd lsNoiseCovariance(const std::vector<NoiseChannel>& channels) {
  if (channels.empty()) throw std::invalid_argument("noise covariance: no channels");
  const Eigen::Index p = channels.front().H.cols();
  Eigen::Index rows = 0;
  for (std::size_t k = 0; k < channels.size(); ++k) {
    checkChannel(channels[k], p, k);
    rows += channels[k].H.rows();
  }
  Eigen::MatrixXd H(rows, p);
  rows = 0;
  for (const NoiseChannel& c : channels) {
    H.middleRows(rows, c.H.rows()) = c.H;
    rows += c.H.rows();
  }
  const ScaledInverse s = scaledInverse(H);
  if (!s.full_rank) return Eigen::MatrixXd::Constant(p, p, kInf);
  // B = sum_c sigma_c^2 G_c^T G_c, G_c = F_c^T H_c D: the covariance of Hs^T (noise).
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(p, p);
  for (const NoiseChannel& c : channels) {
    if (c.sigma_Nm == 0.0) continue;
    const Eigen::MatrixXd G = c.path.transposeApply(c.H * s.scale.asDiagonal());
    B.noalias() += c.sigma_Nm * c.sigma_Nm * (G.transpose() * G);
  }
  const Eigen::MatrixXd Cs = s.inverse * B * s.inverse;
  return s.scale.asDiagonal() * Cs * s.scale.asDiagonal();
}

Eigen::MatrixXd segmentalNoiseCovariance(const NoiseChannel& knee, const NoiseChannel& hip,
                                         const Eigen::MatrixXd& hip_knee_columns) {
  const Eigen::Index pk = knee.H.cols(), ph = hip.H.cols(), p = pk + ph;
  if (hip_knee_columns.rows() != hip.H.rows() || hip_knee_columns.cols() != pk) {
    throw std::invalid_argument("segmental noise covariance: hip_knee_columns must be " +
                                core::toText(hip.H.rows()) + " x " + core::toText(pk) + ", got " +
                                core::toText(hip_knee_columns.rows()) + " x " +
                                core::toText(hip_knee_columns.cols()));
  }
  const Eigen::MatrixXd Ck = lsNoiseCovariance({knee});
  const Eigen::MatrixXd Ch = lsNoiseCovariance({hip});
  if (!Ck.allFinite() || !Ch.allFinite()) return Eigen::MatrixXd::Constant(p, p, kInf);
  // T = A_h H_hk = (H_h^T H_h)^-1 H_h^T H_hk: how a knee-stage error moves the hip estimate.
  const ScaledInverse s = scaledInverse(hip.H);
  const Eigen::MatrixXd T =
      s.scale.asDiagonal() * s.inverse * (hip.H * s.scale.asDiagonal()).transpose() * hip_knee_columns;
  Eigen::MatrixXd C(p, p);
  C.topLeftCorner(ph, ph) = Ch + T * Ck * T.transpose();
  C.topRightCorner(ph, pk) = -T * Ck;
  C.bottomLeftCorner(pk, ph) = C.topRightCorner(ph, pk).transpose();
  C.bottomRightCorner(pk, pk) = Ck;
  return C;
}

Eigen::VectorXd stdOf(const Eigen::MatrixXd& covariance) {
  return covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
}

}  // namespace exoid::ident
