// Welch power spectral density (a port of scipy.signal.welch with a Hann window and constant
// detrend) and the share of the variance above a frequency; see spectrum.hpp.
#include "exoid/ident/signals/spectrum.hpp"

#include "exoid/core/format.hpp"

#include <unsupported/Eigen/FFT>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace exoid::ident {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
// Fewer samples per segment leave <= 4 one-sided bins, all within the Hann main lobe (+-2 bins)
// of DC: no spectrum to speak of.
constexpr Eigen::Index kMinSegmentSamples = 8;

void validateRate(double sample_rate_hz) {
  if (!(sample_rate_hz > 0.0) || !std::isfinite(sample_rate_hz)) {
    throw std::invalid_argument("sample_rate_hz must be positive and finite, got " + core::formatNumber(sample_rate_hz, 12));
  }
}

void validateSamples(const Eigen::Ref<const Eigen::VectorXd>& x) {
  if (x.size() < kMinSegmentSamples) {
    throw std::invalid_argument("x must have at least " + core::toText(kMinSegmentSamples) +
                                " samples, got " + core::toText(x.size()));
  }
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i])) {
      throw std::invalid_argument("x[" + core::toText(i) + "] must be finite, got " + core::formatNumber(x[i], 12));
    }
  }
}

// nperseg: round(segment_s * fs), or the whole record when that is longer (scipy clamps too).
Eigen::Index segmentSamples(Eigen::Index n, double sample_rate_hz, const WelchOptions& options) {
  const double wanted = options.segment_s * sample_rate_hz;  // compared as double: may overflow Index
  if (wanted >= static_cast<double>(n)) return n;
  const auto nperseg = static_cast<Eigen::Index>(std::llround(wanted));
  if (nperseg < kMinSegmentSamples) {
    throw std::invalid_argument("segment_s * sample_rate_hz must round to at least " +
                                core::toText(kMinSegmentSamples) + " samples, got " + core::formatNumber(wanted, 12) +
                                " (segment_s = " + core::formatNumber(options.segment_s, 12) + ")");
  }
  return nperseg;
}

// noverlap = floor(overlap * nperseg); the 1e-9 keeps e.g. 0.29 * 100 = 28.999999999999996 at 29.
Eigen::Index overlapSamples(Eigen::Index nperseg, double overlap) {
  const auto noverlap = static_cast<Eigen::Index>(std::floor(overlap * static_cast<double>(nperseg) + 1e-9));
  return std::min(noverlap, nperseg - 1);  // step >= 1
}

// scipy.signal.get_window('hann', N): the periodic (DFT-even) Hann window.
Eigen::VectorXd periodicHann(Eigen::Index nperseg) {
  const Eigen::ArrayXd i = Eigen::ArrayXd::LinSpaced(nperseg, 0.0, static_cast<double>(nperseg - 1));
  return (0.5 - 0.5 * (2.0 * M_PI / static_cast<double>(nperseg) * i).cos()).matrix();
}

// Adds |FFT(window * (segment - mean))|^2 of one segment to `power` (nperseg / 2 + 1 bins).
class Periodogram {
 public:
  explicit Periodogram(Eigen::Index nperseg)
      : window_(periodicHann(nperseg)), buf_(static_cast<std::size_t>(nperseg)),
        spectrum_(static_cast<std::size_t>(nperseg / 2 + 1)) {
    fft_.SetFlag(Eigen::FFT<double>::HalfSpectrum);  // real input: bins 0 .. nperseg / 2 only
  }
  const Eigen::VectorXd& window() const { return window_; }

  void add(const Eigen::Ref<const Eigen::VectorXd>& segment, Eigen::VectorXd& power) {
    // scipy's order: detrend, then window.
    Eigen::ArrayXd::Map(buf_.data(), window_.size()) = (segment.array() - segment.mean()) * window_.array();
    fft_.fwd(spectrum_.data(), buf_.data(), window_.size());
    for (Eigen::Index k = 0; k < power.size(); ++k) power[k] += std::norm(spectrum_[static_cast<std::size_t>(k)]);
  }

 private:
  Eigen::VectorXd window_;
  std::vector<double> buf_;
  std::vector<std::complex<double>> spectrum_;
  Eigen::FFT<double> fft_;
};

// Share of bin k's band [f_k - df/2, f_k + df/2], clipped to [0, nyquist], that lies above f_hz.
double shareAbove(double f_k, double df, double nyquist_hz, double f_hz) {
  const double lo = std::max(0.0, f_k - 0.5 * df);
  const double hi = std::min(nyquist_hz, f_k + 0.5 * df);
  return std::clamp((hi - std::max(lo, f_hz)) / (hi - lo), 0.0, 1.0);
}

}  // namespace

void WelchOptions::validate() const {
  if (!(segment_s > 0.0) || !std::isfinite(segment_s)) {
    throw std::invalid_argument("'segment_s' must be positive and finite, got " + core::formatNumber(segment_s, 12));
  }
  if (!(overlap >= 0.0 && overlap < 1.0)) {
    throw std::invalid_argument("'overlap' must be in [0, 1), got " + core::formatNumber(overlap, 12));
  }
}

PowerSpectrum welchPsd(const Eigen::Ref<const Eigen::VectorXd>& x, double sample_rate_hz,
                       const WelchOptions& options) {
  options.validate();
  validateRate(sample_rate_hz);
  validateSamples(x);
  const Eigen::Index nperseg = segmentSamples(x.size(), sample_rate_hz, options);
  const Eigen::Index step = nperseg - overlapSamples(nperseg, options.overlap);
  const Eigen::Index segments = (x.size() - nperseg) / step + 1;  // trailing partial one dropped
  const Eigen::Index bins = nperseg / 2 + 1;

  Periodogram periodogram(nperseg);
  Eigen::VectorXd power = Eigen::VectorXd::Zero(bins);
  for (Eigen::Index s = 0; s < segments; ++s) periodogram.add(x.segment(s * step, nperseg), power);

  PowerSpectrum out;
  out.df_Hz = sample_rate_hz / static_cast<double>(nperseg);
  out.frequency_Hz = out.df_Hz * Eigen::VectorXd::LinSpaced(bins, 0.0, static_cast<double>(bins - 1));
  // Density scaling 1 / (fs sum w^2), averaged over segments. One-sided: bins 0 < k < nperseg/2
  // fold in their negative-frequency twins; DC and an even nperseg's Nyquist bin have none.
  out.density = power / (sample_rate_hz * periodogram.window().squaredNorm() * static_cast<double>(segments));
  for (Eigen::Index k = 1; 2 * k < nperseg; ++k) out.density[k] *= 2.0;
  return out;
}

double varianceFractionAbove(const Eigen::Ref<const Eigen::VectorXd>& x, double sample_rate_hz, double f_hz,
                             const WelchOptions& options) {
  validateRate(sample_rate_hz);
  const double nyquist_hz = sample_rate_hz / 2.0;
  if (!(f_hz > 0.0 && f_hz < nyquist_hz)) {  // also rejects NaN
    throw std::invalid_argument("f_hz must be in (0, " + core::formatNumber(nyquist_hz, 12) + ") Hz, got " + core::formatNumber(f_hz, 12));
  }
  const PowerSpectrum p = welchPsd(x, sample_rate_hz, options);
  double total = 0.0, above = 0.0;
  for (Eigen::Index k = 1; k < p.density.size(); ++k) {  // DC left out
    total += p.density[k];
    above += p.density[k] * shareAbove(p.frequency_Hz[k], p.df_Hz, nyquist_hz, f_hz);
  }
  // Mean removal leaves ~nperseg eps max|x| of rounding in each sample of a constant segment;
  // a variance below that square is no signal, and its split would be noise.
  const auto nperseg = static_cast<double>(segmentSamples(x.size(), sample_rate_hz, options));
  const double rounding = nperseg * kEps * x.cwiseAbs().maxCoeff();
  if (total * p.df_Hz <= rounding * rounding) return 0.0;
  return above / total;
}

}  // namespace exoid::ident
