#pragma once
// Differentiation and zero-phase low-pass filtering of sampled signals (columns = channels).
#include <Eigen/Core>

namespace exoid::ident {

enum class Differentiation {
  kForward,  ///< (x[i+1] - x[i]) / dt (the paper); last sample uses the backward difference
  kCentral,  ///< (x[i+1] - x[i-1]) / (2 dt); first/last samples one-sided
  /// Five-point central differences (x[i-2] - 8 x[i-1] + 8 x[i+1] - x[i+2]) / (12 dt): error
  /// (w dt)^4 / 30 of a sine (5e-11 at 1 Hz and 1 kHz, where kCentral's (w dt)^2 / 6 is 7e-6);
  /// the two samples next to each end use kCentral, the ends one-sided differences.
  kCentral4,
};
/// "forward", "central", "central4".
const char* toString(Differentiation d);

/// d/dt of each column of x sampled every dt_s seconds; same shape as x. Exact for polynomials
/// of degree 1 (kForward) and, in the interior, of degree 2 (kCentral); truncation error O(dt)
/// and O(dt^2). Throws std::invalid_argument unless x has >= 2 rows and dt_s > 0 is finite.
Eigen::MatrixXd differentiate(const Eigen::MatrixXd& x, double dt_s, Differentiation method);

/// A digital IIR filter as second-order sections, each row [b0 b1 b2 a0 a1 a2] with a0 = 1
/// (scipy's sos layout).
struct SosFilter {
  Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor> sos;
  Eigen::Index sections() const { return sos.rows(); }
};

/// Digital Butterworth low-pass of the given order (1..12) and cutoff (-3 dB) at cutoff_hz,
/// for samples at sample_rate_hz: scipy.signal.butter(order, cutoff_hz, fs=sample_rate_hz,
/// output='sos'), i.e. bilinear transform with prewarping (|H| = 1/sqrt(2) exactly at the
/// cutoff) and scipy's 'nearest' pole-zero pairing into ceil(order / 2) sections. The gain sits
/// in the first section and makes the DC gain of the stored coefficients 1 (to rounding).
/// Throws std::invalid_argument unless 1 <= order <= 12, sample_rate_hz > 0 and
/// 0 < cutoff_hz < sample_rate_hz / 2.
SosFilter butterworthLowpass(int order, double cutoff_hz, double sample_rate_hz);

/// Causal filtering of each column from rest (scipy.signal.sosfilt): direct form II transposed,
/// section after section. Throws std::invalid_argument unless f has >= 1 section, finite
/// coefficients and a0 = 1 in every section.
Eigen::MatrixXd sosfilt(const SosFilter& f, const Eigen::MatrixXd& x);

/// Zero-phase forward-backward filtering of each column, with scipy.signal.sosfiltfilt's
/// default edge handling: odd extension of padlen = 3 * (2 * sections + 1 - m) samples at each
/// end, where m = min(#sections with b2 = 0, #sections with a2 = 0) (1 for an odd-order
/// Butterworth, else 0), and steady-state initial conditions (sosfilt_zi) scaled by the first
/// sample of the padded signal for the forward pass and by the last forward output for the
/// backward pass. Magnitude response |H|^2, zero phase; a constant comes back unchanged.
/// Throws std::invalid_argument unless x.rows() > padlen, f is valid for sosfilt and no
/// section has a pole at z = 1.
Eigen::MatrixXd filtfilt(const SosFilter& f, const Eigen::MatrixXd& x);
/// filtfilt into x itself, bit for bit the same values: no second matrix of x's size (a long
/// record's block filters its regressor columns where they are).
void filtfiltInPlace(const SosFilter& f, Eigen::Ref<Eigen::MatrixXd> x);

}  // namespace exoid::ident
