#pragma once
// Differentiation and zero-phase low-pass filtering of sampled signals (columns = channels).
#include <Eigen/Core>

namespace exoid::ident {

enum class Differentiation {
  kForward,  ///< (x[i+1] - x[i]) / dt (the paper); last sample uses the backward difference
  kCentral,  ///< (x[i+1] - x[i-1]) / (2 dt); first/last samples one-sided
};

/// d/dt of each column of x sampled every dt_s seconds. Requires >= 2 rows, dt_s > 0.
Eigen::MatrixXd differentiate(const Eigen::MatrixXd& x, double dt_s, Differentiation method);

/// A digital IIR filter as second-order sections, each row [b0 b1 b2 a0 a1 a2] with a0 = 1
/// (scipy's sos layout).
struct SosFilter {
  Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor> sos;
  Eigen::Index sections() const { return sos.rows(); }
};

/// Digital Butterworth low-pass of the given order (1..12) and cutoff (-3 dB) at cutoff_hz,
/// for samples at sample_rate_hz (bilinear transform with prewarping, as scipy.signal.butter).
/// Throws std::invalid_argument unless 0 < cutoff_hz < sample_rate_hz / 2.
SosFilter butterworthLowpass(int order, double cutoff_hz, double sample_rate_hz);

/// Causal filtering of each column from rest (scipy.signal.sosfilt).
Eigen::MatrixXd sosfilt(const SosFilter& f, const Eigen::MatrixXd& x);

/// Zero-phase forward-backward filtering of each column, with scipy.signal.sosfiltfilt's
/// default edge handling: odd extension of padlen = 3 * (2 * sections + 1) samples at each end
/// and steady-state initial conditions (sosfilt_zi) scaled by the first sample.
/// Requires x.rows() > padlen. Magnitude response |H|^2, zero phase.
Eigen::MatrixXd filtfilt(const SosFilter& f, const Eigen::MatrixXd& x);

}  // namespace exoid::ident
