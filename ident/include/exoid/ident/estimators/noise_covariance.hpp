#pragma once
// The noise-limited covariance of a least-squares estimate, for the regressor the estimator
// actually fits and the torque noise as it reaches the fit.
//
// White torque-sensor noise e (std sigma per sample) reaches the fitted torque as F e, where F is
// the processing's linear map: the zero-phase low-pass (when the torque is filtered) followed by
// the edge trim. For y = H x + F e the LS estimate x = (H^T H)^-1 H^T y has the covariance
//   C = sigma^2 (H^T H)^-1 (F^T H)^T (F^T H) (H^T H)^-1          (the "sandwich")
// With F = I (raw torque) this is sigma^2 (H^T H)^-1, the Cramer-Rao bound of the linear Gaussian
// model. With a filter it is the exact covariance of LS on the filtered data; when H is itself
// in the filter's pass band (filtered columns) F^T H ~ H and it reduces to sigma^2 (H^T H)^-1 of the
// FILTERED regressor. What it never equals is the bound of the raw, unfiltered states: those carry
// frequencies no estimator working in the pass band sees.
#include "exoid/ident/signals/preprocess.hpp"
#include "exoid/ident/signals/signals.hpp"

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace exoid::ident {

/// How raw torque noise reaches the rows an estimator fits: optional forward-backward filter,
/// then `trim` samples dropped at each end of a record of `raw_rows` samples.
struct TorqueNoisePath {
  std::optional<SosFilter> filter;  ///< one pass; applied forward and backward (filtfilt)
  Eigen::Index trim = 0;
  Eigen::Index raw_rows = 0;
  int decimation = 1;  ///< every decimation-th trimmed row is fitted (parallel processing)
  Eigen::Index fittedRows() const { return (raw_rows - 2 * trim + decimation - 1) / decimation; }
  /// F^T H for H with fittedRows() rows: a raw_rows x H.cols() matrix. The trimmed rows of
  /// filtfilt are a stationary convolution with the filter's symmetric kernel |h|^2 (its edge
  /// handling has decayed once trim exceeds the filter's settling, e.g. 5e-6 of the kernel at the
  /// default 3 / cutoff), so F^T H is that same convolution of the zero-extended H.
  Eigen::MatrixXd transposeApply(const Eigen::MatrixXd& H) const;
};

/// The path of the torque through `processRecord(d, c, o)` for a record of raw_rows samples at
/// sample_rate_hz. Paper processing: the filter when o.filter && o.filter_torque, and
/// o.edgeTrimSamples(). Parallel processing: the filter when o.filter, the trim and
/// o.decimationFactor(). Throws on invalid options.
TorqueNoisePath torqueNoisePath(const SignalOptions& o, double sample_rate_hz, Eigen::Index raw_rows);
/// A path without filter (raw torque), trimmed by `trim` at each end.
TorqueNoisePath rawTorquePath(Eigen::Index raw_rows, Eigen::Index trim);

/// Rows of a fit that carry one independent noise channel (one joint's torque of one record):
/// the fitted regressor rows in time order, the channel's path and its white-noise std (N m).
struct NoiseChannel {
  Eigen::MatrixXd H;
  TorqueNoisePath path;
  double sigma_Nm = 0.0;
};

/// Covariance of the LS estimate over the channels' rows stacked (any row order gives the same
/// estimate). p x p; every entry +inf when the stacked regressor is rank deficient (column-scaled
/// pivoted QR, relative tolerance 1e-8, as least squares). Throws std::invalid_argument when a
/// channel's rows do not match its path, the column counts differ or a sigma is negative.
Eigen::MatrixXd lsNoiseCovariance(const std::vector<NoiseChannel>& channels);

/// The segmental strategy (paper Eq. 9): the knee stage estimates x_k from `knee`; the hip stage
/// fits x_h to y_h - H_hk x_k from `hip`, whose noise is independent of the knee stage's (another
/// record). Then x_h = A_h (y_h + F e_h - H_hk x_k), A_h = (H_h^T H_h)^-1 H_h^T, so
///   cov(x_h) = C_h + (A_h H_hk) C_k (A_h H_hk)^T,  cov(x_h, x_k) = -(A_h H_hk) C_k.
/// Returns the covariance of [x_h; x_k] (the order of X). hip_knee_columns = H_hk, the hip
/// equation's knee columns on the hip stage's rows.
Eigen::MatrixXd segmentalNoiseCovariance(const NoiseChannel& knee, const NoiseChannel& hip,
                                         const Eigen::MatrixXd& hip_knee_columns);

/// sqrt of the diagonal (inf stays inf).
Eigen::VectorXd stdOf(const Eigen::MatrixXd& covariance);

}  // namespace exoid::ident
