#pragma once
// Power spectral density by Welch's method and the share of a signal's variance above a
// frequency (e.g. how much of a joint torque is controller chatter rather than motion).
#include <Eigen/Core>

namespace exoid::ident {

/// scipy.signal.welch(x, fs, window='hann', nperseg, noverlap, detrend='constant',
/// scaling='density') with nperseg = round(segment_s * fs) and
/// noverlap = floor(overlap * nperseg) (scipy's default nperseg // 2 for overlap = 0.5).
struct WelchOptions {
  /// Segment length in seconds; the resolution is df = 1 / segment_s. Range > 0. Default 2 s:
  /// df = 0.5 Hz, so a 1 Hz gait motion falls on a bin (two whole periods per segment, no
  /// leakage beyond the Hann window's +-1 bin, i.e. nothing above 1.5 Hz) and is cleanly
  /// separated from a 10 Hz threshold, while a 10 s log still averages 9 segments (50 %
  /// overlap), ~17 degrees of freedom per bin. A record shorter than one segment is analysed
  /// as a single segment of its full length (scipy does the same, with a warning).
  double segment_s = 2.0;
  /// Fraction of a segment shared with the next. Range [0, 1). Default 0.5, scipy's default
  /// and where the Hann window's overlapped segments are still nearly independent (the
  /// correlation of their windows is 1/6).
  double overlap = 0.5;
  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

/// One-sided power spectral density at frequencies k * df, k = 0 .. nperseg / 2 (rounded down).
struct PowerSpectrum {
  Eigen::VectorXd frequency_Hz;
  /// Per Hz, one-sided: sum(density) * df_Hz is the Hann-weighted mean square of the
  /// mean-removed segments (Parseval), i.e. the variance for a stationary signal.
  Eigen::VectorXd density;
  double df_Hz = 0.0;  ///< sample_rate_hz / nperseg
};

/// Welch's estimate, scipy's conventions exactly: periodic Hann window w_i = 0.5 - 0.5 cos(2 pi
/// i / nperseg); floor((n - nperseg) / step) + 1 segments starting at multiples of
/// step = nperseg - noverlap (a trailing partial segment is dropped); each segment's mean is
/// subtracted before windowing; the periodograms |FFT(w * segment)|^2 / (fs * sum(w^2)) are
/// averaged and every bin except DC and (for even nperseg) Nyquist is doubled.
/// Throws std::invalid_argument unless sample_rate_hz > 0 is finite, every sample is finite,
/// options are valid and both x.size() and nperseg are at least 8 (fewer leaves <= 4 bins, all
/// inside the Hann main lobe of DC).
PowerSpectrum welchPsd(const Eigen::Ref<const Eigen::VectorXd>& x, double sample_rate_hz,
                       const WelchOptions& options = {});

/// Fraction of the (mean-removed) variance above f_hz: the integral of welchPsd over
/// (f_hz, fs/2] divided by the integral over (0, fs/2], both as sum(density) * df with the DC
/// bin left out. Bins straddling f_hz are split linearly: bin k stands for the band
/// [f_k - df/2, f_k + df/2] clipped to [0, fs/2], and its power is spread evenly over that band
/// (so f_hz on a bin centre counts half that bin, and for f_hz = (k + 1/2) df this is scipy's
/// P[f > f_hz].sum() / P[1:].sum()). The result is continuous in f_hz and exact in expectation
/// for white noise. A signal whose segments are constant to rounding (variance below
/// (nperseg eps max|x|)^2) has nothing to split and gives 0.
/// Throws as welchPsd and unless 0 < f_hz < sample_rate_hz / 2.
double varianceFractionAbove(const Eigen::Ref<const Eigen::VectorXd>& x, double sample_rate_hz, double f_hz,
                             const WelchOptions& options = {});

}  // namespace exoid::ident
