// Tests for spectrum.hpp. Ground truth: Parseval (the PSD integrates to the variance), the
// closed-form DFT of the periodic Hann window (power at bins 0, +-1 only, in the ratio 4 : 1),
// the first two moments of the Welch estimate of Gaussian white noise, and a direct O(N^2) DFT
// written from scipy.signal.welch's recipe (scipy is not installed here, so there are no scipy
// numbers to hard-code).
#include "exoid/ident/signals/spectrum.hpp"

#include "exoid/core/random.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace exoid::ident {
namespace {

using test::expectInvalidArgumentMentioning;

constexpr double kSpectrumPi = 3.14159265358979323846;
constexpr double kSpectrumEps = std::numeric_limits<double>::epsilon();
// A 10 s log at 1 kHz with the default 2 s segments: nperseg 2000, step 1000, 9 segments.
constexpr double kSpectrumFs_Hz = 1000.0;
constexpr Eigen::Index kN = 10000;
constexpr Eigen::Index kSegment = 2000;
constexpr Eigen::Index kSegments = 9;

// ---- Tolerances, in one place -----------------------------------------------------------------
namespace tol {
// Statistical checks pass within this many standard deviations: a false failure has probability
// ~6e-7 per check, whatever the seed.
constexpr double kSigmas = 5.0;

// Rounding of a Welch integral (or a sum of some of its bins) of a sum of tones, relative to
// (sum |A|)^2 >= max x^2. Samples: the argument 2 pi r / N (r < N exact) is rounded to ~3 eps
// * 2 pi, plus sin and the sum: <= 20 eps sum|A| per sample, entering the square twice (40).
// Detrend, window and |.|^2: 4 eps. FFT: 2 x ~3 eps per radix stage. Summing N/2 bins and K
// segments: (N/2 + K) eps (worst case of naive summation).
double tonesRounding(Eigen::Index nperseg, Eigen::Index segments, double sum_abs_amplitude) {
  const double n = static_cast<double>(nperseg);
  return (44.0 + 6.0 * std::log2(n) + n / 2.0 + static_cast<double>(segments)) * kSpectrumEps * sum_abs_amplitude *
         sum_abs_amplitude;
}

// Standard deviation of the Welch integral of Gaussian white noise over sigma^2, for K Hann
// segments of N samples at 50 % overlap. One segment's integral is x' A x with A = diag(w^2) /
// sum(w^2) (mean removal changes it by O(1/N)): var = 2 sigma^4 sum(w^4) / sum(w^2)^2 =
// 2 (35N/128) / (3N/8)^2 = 35 / (9N). Neighbours share half a segment: cov = 2 sigma^4
// sum_i w_i^2 w_{i+N/2}^2 / sum(w^2)^2 = 2 (3N/256) / (3N/8)^2 = 1 / (6N); further ones nothing.
// Checked by Monte Carlo (4000 records): predicted 0.01525, observed 0.01504.
double whiteIntegralSd(Eigen::Index segments, Eigen::Index nperseg) {
  const double k = static_cast<double>(segments), n = static_cast<double>(nperseg);
  return std::sqrt((35.0 * k / 9.0 + (k - 1.0) / 3.0) / (k * k * n));
}

// Standard deviation of the fraction R = U / (U + L) of white noise above f (U above, L below),
// by the delta method: var R = R^2 (1 - R)^2 (var U / U^2 + var L / L^2). A band of M bins has
// var / mean^2 = g / M with g = (35/18) (K + 2 (K - 1) (3/70)) / K^2, the whole-band figures
// above per bin pair (35/18 counts the correlation of neighbouring Hann bins, 3/70 that of
// overlapping segments; both are upper bounds for part of the band, and the positive
// correlation of U and L across f only lowers var R). Monte Carlo (4000 records, f = 10, 100,
// 250, 450 Hz): predicted 0.00216, 0.00611, 0.00763, 0.00458; observed 0.00208, 0.00615,
// 0.00774, 0.00459.
double whiteFractionSd(double fraction, double bins_above, double bins_below, Eigen::Index segments) {
  const double k = static_cast<double>(segments);
  const double g = 35.0 / 18.0 * (k + 2.0 * (k - 1.0) * 3.0 / 70.0) / (k * k);
  return fraction * (1.0 - fraction) * std::sqrt(g * (1.0 / bins_above + 1.0 / bins_below));
}

// Share of a Hann-windowed tone's power farther than K bins from it: |W(d)|^2 / |W(0)|^2 ->
// sinc(d)^2 / (1 - d^2)^2 <= (16/9) / (pi^2 d^6) for d >= 2; summed over both sides (<= 2
// int_{K-1}^inf, K the distance of the nearest bin left out) and divided by the window's total
// energy N sum(w^2) / |W(0)|^2 = 3/2: 0.048 / (K - 1)^5. Times 100 for the finite-N form of W
// and the negative-frequency image's cross term (2 sqrt(its own tail beyond 2b - K bins), ~1e-7
// for the case below).
double hannLeakageBeyond(double nearest_left_out) {
  return 100.0 * (2.0 / 3.0) * 2.0 * (16.0 / 9.0) / (5.0 * kSpectrumPi * kSpectrumPi * std::pow(nearest_left_out - 1.0, 5.0));
}
}  // namespace tol

// ---- Helpers ----------------------------------------------------------------------------------

// A tone A sin(2 pi bin i / N + phase): `bin` whole periods in every N-sample segment.
struct Tone {
  Eigen::Index bin;
  double amplitude;
  double phase;
};

// The argument is reduced exactly ((bin i) mod N) so it carries no rounding from a long time axis.
Eigen::VectorXd tones(Eigen::Index n, Eigen::Index nperseg, const std::vector<Tone>& ts) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  for (const Tone& t : ts) {
    for (Eigen::Index i = 0; i < n; ++i) {
      const double r = static_cast<double>((t.bin * i) % nperseg);
      x[i] += t.amplitude * std::sin(2.0 * kSpectrumPi * r / static_cast<double>(nperseg) + t.phase);
    }
  }
  return x;
}

double sumAbsAmplitude(const std::vector<Tone>& ts) {
  double s = 0.0;
  for (const Tone& t : ts) s += std::abs(t.amplitude);
  return s;
}

// Tones whose windowed powers add up exactly: the Hann window squared has DFT bins 0, +-1, +-2
// only, so sum_i w_i^2 x_i^2 = sum (A^2/2) sum w^2 needs every tone's doubled bin and every sum
// and difference of two tones' bins at >= 3 bins from a multiple of N.
bool tonesAddUp(const std::vector<Tone>& ts, Eigen::Index nperseg) {
  for (std::size_t a = 0; a < ts.size(); ++a) {
    for (std::size_t b = a; b < ts.size(); ++b) {
      const Eigen::Index sum = ts[a].bin + ts[b].bin, diff = std::abs(ts[a].bin - ts[b].bin);
      if (sum < 3 || sum > nperseg - 3 || (a != b && diff < 3)) return false;
    }
  }
  return true;
}

// Gaussian white noise of standard deviation sigma (Box-Muller, cosine branch).
Eigen::VectorXd whiteNoise(Eigen::Index n, double sigma, std::uint64_t seed) {
  core::Rng rng(seed);
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double u1 = 1.0 - rng.uniform(), u2 = rng.uniform();  // u1 in (0, 1]
    x[i] = sigma * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kSpectrumPi * u2);
  }
  return x;
}

// sum(density[first..last]) * df.
double bandPower(const PowerSpectrum& p, Eigen::Index first, Eigen::Index last) {
  return p.density.segment(first, last - first + 1).sum() * p.df_Hz;
}

// ---- welchPsd ---------------------------------------------------------------------------------

TEST(WelchPsd, DefaultsGiveHalfHertzBinsUpToNyquistAndUseAShortRecordWhole) {
  const WelchOptions defaults;
  EXPECT_EQ(defaults.segment_s, 2.0);
  EXPECT_EQ(defaults.overlap, 0.5);
  const PowerSpectrum p = welchPsd(whiteNoise(kN, 1.0, 1), kSpectrumFs_Hz);
  EXPECT_EQ(p.df_Hz, 0.5);
  ASSERT_EQ(p.frequency_Hz.size(), kSegment / 2 + 1);
  ASSERT_EQ(p.density.size(), p.frequency_Hz.size());
  for (Eigen::Index k = 0; k < p.frequency_Hz.size(); ++k) EXPECT_EQ(p.frequency_Hz[k], 0.5 * static_cast<double>(k)) << k;
  // 1.5 s < one segment: a single segment of all 1500 samples (odd bin count 751, df = 2/3 Hz).
  const PowerSpectrum short_p = welchPsd(whiteNoise(1500, 1.0, 2), kSpectrumFs_Hz);
  EXPECT_EQ(short_p.df_Hz, kSpectrumFs_Hz / 1500.0);
  EXPECT_EQ(short_p.density.size(), 751);
}

TEST(WelchPsd, ParsevalIsExactToRoundingForTonesThatFitTheSegments) {
  // Hann leakage spreads each tone over bins m-1..m+1 but creates no power: with whole periods
  // per segment the segment means are 0 and the cross terms vanish (tonesAddUp), so the
  // integral is sum A^2/2 up to rounding alone. A tone off the grid would be off by ~1e-5 here.
  const std::vector<Tone> ts = {{2, 1.0, 0.3}, {14, 0.5, 1.1}, {80, 0.3, -0.7}, {247, 0.2, 2.0}};
  ASSERT_TRUE(tonesAddUp(ts, kSegment));
  double variance = 0.0;
  for (const Tone& t : ts) variance += t.amplitude * t.amplitude / 2.0;
  const PowerSpectrum p = welchPsd(tones(kN, kSegment, ts), kSpectrumFs_Hz);
  const double tol = tol::tonesRounding(kSegment, kSegments, sumAbsAmplitude(ts));
  EXPECT_NEAR(p.density.sum() * p.df_Hz, variance, tol);
  EXPECT_LT(tol / variance, 1e-11);  // rounding level indeed
}

TEST(WelchPsd, ParsevalHoldsForWhiteNoiseWithinTheEstimatorsSpread) {
  // E[integral] = sigma^2 (1 - 1/N): mean removal takes one of N degrees of freedom per segment.
  const double sigma = 1.5;
  for (const std::uint64_t seed : {11u, 12u, 13u}) {
    const PowerSpectrum p = welchPsd(whiteNoise(kN, sigma, seed), kSpectrumFs_Hz);
    const double expected = sigma * sigma * (1.0 - 1.0 / static_cast<double>(kSegment));
    EXPECT_NEAR(p.density.sum() * p.df_Hz, expected,
                tol::kSigmas * sigma * sigma * tol::whiteIntegralSd(kSegments, kSegment))
        << "seed " << seed;
  }
}

TEST(WelchPsd, ToneOnABinHasASquaredOverTwoInItsThreeBinsInTheRatio1To4To1) {
  // The periodic Hann window's DFT is N/2 at bin 0 and -N/4 at +-1, zero elsewhere: a tone on
  // bin m puts 1/6, 4/6, 1/6 of its power A^2/2 into bins m-1, m, m+1 and nothing elsewhere.
  const double a = 2.5;
  const std::vector<Tone> ts = {{80, a, 0.4}};  // 40 Hz
  const PowerSpectrum p = welchPsd(tones(kN, kSegment, ts), kSpectrumFs_Hz);
  const double power = a * a / 2.0, tol = tol::tonesRounding(kSegment, kSegments, a);
  EXPECT_EQ(p.frequency_Hz[80], 40.0);
  EXPECT_NEAR(bandPower(p, 79, 81), power, tol);
  EXPECT_NEAR(bandPower(p, 80, 80), power * 4.0 / 6.0, tol);
  EXPECT_NEAR(bandPower(p, 79, 79), power / 6.0, tol);
  EXPECT_NEAR(bandPower(p, 81, 81), power / 6.0, tol);
  EXPECT_NEAR(bandPower(p, 0, 78) + bandPower(p, 82, p.density.size() - 1), 0.0, tol);
}

TEST(WelchPsd, ToneHalfwayBetweenBinsStillIntegratesToASquaredOverTwo) {
  // 100.25 Hz sits between bins 200 and 201: the peak bins hold ~48 % each (scalloping), yet
  // the band around it holds A^2/2. The window's DFT (bins 0, +-1) keeps the mean removal out of
  // that band, so by Parseval the band holds sum w^2 x^2 / sum w^2 = A^2/2 (the tone's doubled
  // frequency is the whole bin 401, where w^2 has no component) less the leakage beyond it.
  const double a = 2.5, f0 = 100.25, power = a * a / 2.0;
  Eigen::VectorXd x(kN);
  for (Eigen::Index i = 0; i < kN; ++i) {
    // 100.25 Hz = 401 cycles per 4 s: reduce the argument exactly, as in tones().
    const double r = static_cast<double>((401 * i) % 4000);
    x[i] = a * std::sin(2.0 * kSpectrumPi * r / 4000.0 + 0.9);
  }
  const PowerSpectrum p = welchPsd(x, kSpectrumFs_Hz);
  // Bins 181 .. 220 lie within 19.5 bins of f0; the nearest ones left out are 20.5 bins away.
  const Eigen::Index below = 200, half_width = 20;
  ASSERT_EQ(p.frequency_Hz[below], f0 - 0.25);
  const double tol = tol::hannLeakageBeyond(static_cast<double>(half_width) + 0.5) * power +
                     tol::tonesRounding(kSegment, kSegments, a);
  EXPECT_NEAR(bandPower(p, below - half_width + 1, below + half_width), power, tol);
  EXPECT_LT(tol / power, 1e-5);
  EXPECT_LT(bandPower(p, below, below), 0.6 * power);  // the peak bin alone misses > 40 %
}

// scipy.signal.welch(x, fs, window='hann', nperseg, noverlap, detrend='constant',
// scaling='density') computed directly: whole segments only, mean removed, window sin^2(pi i/N)
// (= 0.5 - 0.5 cos(2 pi i / N)), DFT by definition, scale 1 / (fs sum w^2), averaged, then
// P[1:-1] *= 2 for even N and P[1:] *= 2 for odd N.
struct DirectWelch {
  Eigen::VectorXd density;
  Eigen::Index segments = 0;
  double tol = 0.0;  // rounding bound on each bin, for this and for an FFT-based result
};

DirectWelch directWelch(const Eigen::VectorXd& x, double fs, Eigen::Index nperseg, Eigen::Index noverlap) {
  const Eigen::Index bins = nperseg / 2 + 1;
  const double n = static_cast<double>(nperseg);
  Eigen::VectorXd w(nperseg);
  for (Eigen::Index i = 0; i < nperseg; ++i) w[i] = std::pow(std::sin(kSpectrumPi * static_cast<double>(i) / n), 2);
  DirectWelch out;
  out.density = Eigen::VectorXd::Zero(bins);
  double max_l1 = 0.0;
  for (Eigen::Index start = 0; start + nperseg <= x.size(); start += nperseg - noverlap) {
    ++out.segments;
    const Eigen::ArrayXd d = x.segment(start, nperseg).array() - x.segment(start, nperseg).mean();
    max_l1 = std::max(max_l1, d.abs().sum());
    for (Eigen::Index k = 0; k < bins; ++k) {
      std::complex<double> sum = 0.0;
      for (Eigen::Index i = 0; i < nperseg; ++i)
        sum += d[i] * w[i] * std::polar(1.0, -2.0 * kSpectrumPi * static_cast<double>((k * i) % nperseg) / n);
      out.density[k] += std::norm(sum);
    }
  }
  const double scale = 1.0 / (fs * w.squaredNorm());
  out.density *= scale / static_cast<double>(out.segments);
  const Eigen::Index last_doubled = nperseg % 2 == 0 ? bins - 2 : bins - 1;
  out.density.segment(1, last_doubled) *= 2.0;
  // Each DFT sum: N products and additions plus the twiddle's rounding, (N + 6) eps sum|d w|;
  // the FFT adds ~3 eps per stage. |X|^2 doubles the relative error, and |X| <= sum|d|; doubled
  // bins twice that.
  out.tol = 2.0 * 2.0 * (n + 6.0 + 3.0 * std::log2(n)) * kSpectrumEps * max_l1 * max_l1 * scale;
  return out;
}

TEST(WelchPsd, MatchesADirectDftOfScipysRecipe) {
  struct Case {
    Eigen::Index n;
    double fs_hz, segment_s, overlap;
    Eigen::Index nperseg, noverlap, segments;  // scipy's arguments and its segment count
  };
  const Case cases[] = {
      {16, 8.0, 1.0, 0.5, 8, 4, 3},     // the basic case
      {17, 8.0, 1.0, 0.5, 8, 4, 3},     // sample 16 left over: dropped
      {19, 8.0, 1.125, 0.5, 9, 4, 3},   // odd nperseg: no Nyquist bin, noverlap = 9 // 2
      {16, 8.0, 1.0, 0.75, 8, 6, 5},    // more overlap
      {16, 8.0, 1.0, 0.0, 8, 0, 2},     // none
      {12, 8.0, 2.0, 0.5, 12, 6, 1},    // record shorter than a segment: used whole
  };
  for (const Case& c : cases) {
    Eigen::VectorXd x(c.n);  // a trend and an offset, so that mean removal matters
    for (Eigen::Index i = 0; i < c.n; ++i)
      x[i] = 3.0 + 0.1 * static_cast<double>(i) + static_cast<double>((37 * i) % 23) / 23.0;
    const PowerSpectrum p = welchPsd(x, c.fs_hz, WelchOptions{c.segment_s, c.overlap});
    const DirectWelch ref = directWelch(x, c.fs_hz, c.nperseg, c.noverlap);
    ASSERT_EQ(ref.segments, c.segments) << "n " << c.n;
    ASSERT_EQ(p.density.size(), ref.density.size()) << "n " << c.n;
    EXPECT_EQ(p.df_Hz, c.fs_hz / static_cast<double>(c.nperseg));
    for (Eigen::Index k = 0; k < p.density.size(); ++k) {
      EXPECT_EQ(p.frequency_Hz[k], static_cast<double>(k) * p.df_Hz);
      EXPECT_NEAR(p.density[k], ref.density[k], ref.tol) << "n " << c.n << " N " << c.nperseg << " bin " << k;
    }
    EXPECT_LT(ref.tol, 1e-12 * ref.density.maxCoeff());
  }
}

TEST(WelchPsd, DropsTheTrailingPartialSegment) {
  // n = 17, nperseg 8, step 4: segments start at 0, 4, 8; sample 16 is never used.
  Eigen::VectorXd x = whiteNoise(17, 1.0, 5);
  const WelchOptions o{1.0, 0.5};
  const PowerSpectrum p = welchPsd(x, 8.0, o);
  x[16] += 100.0;
  EXPECT_EQ(welchPsd(x, 8.0, o).density, p.density);
  x[15] += 100.0;
  EXPECT_NE(welchPsd(x, 8.0, o).density, p.density);
}

TEST(WelchPsd, RejectsBadArguments) {
  const Eigen::VectorXd x = whiteNoise(100, 1.0, 3);
  expectInvalidArgumentMentioning([&] { welchPsd(x, 0.0); }, "sample_rate_hz must be positive and finite, got 0");
  expectInvalidArgumentMentioning([&] { welchPsd(x, -5.0); }, "got -5");
  expectInvalidArgumentMentioning([&] { welchPsd(x, std::nan("")); }, "got nan");
  expectInvalidArgumentMentioning([&] { welchPsd(x, std::numeric_limits<double>::infinity()); }, "got inf");
  Eigen::VectorXd bad = x;
  bad[7] = std::nan("");
  expectInvalidArgumentMentioning([&] { welchPsd(bad, kSpectrumFs_Hz); }, "x[7] must be finite, got nan");
  bad[7] = -std::numeric_limits<double>::infinity();
  expectInvalidArgumentMentioning([&] { welchPsd(bad, kSpectrumFs_Hz); }, "x[7] must be finite, got -inf");
  expectInvalidArgumentMentioning([&] { welchPsd(x.head(7), kSpectrumFs_Hz); }, "at least 8 samples, got 7");
  EXPECT_NO_THROW(welchPsd(x.head(8), kSpectrumFs_Hz));
  expectInvalidArgumentMentioning([&] { welchPsd(x, kSpectrumFs_Hz, WelchOptions{0.005, 0.5}); },
                                  "segment_s * sample_rate_hz must round to at least 8 samples, got 5");
  expectInvalidArgumentMentioning([&] { welchPsd(x, kSpectrumFs_Hz, WelchOptions{0.0, 0.5}); },
                                  "'segment_s' must be positive and finite, got 0");
  expectInvalidArgumentMentioning([&] { welchPsd(x, kSpectrumFs_Hz, WelchOptions{std::nan(""), 0.5}); }, "got nan");
  expectInvalidArgumentMentioning([&] { welchPsd(x, kSpectrumFs_Hz, WelchOptions{2.0, 1.0}); },
                                  "'overlap' must be in [0, 1), got 1");
  expectInvalidArgumentMentioning([&] { welchPsd(x, kSpectrumFs_Hz, WelchOptions{2.0, -0.1}); }, "got -0.1");
}

// ---- varianceFractionAbove --------------------------------------------------------------------

TEST(SpectrumVarianceFraction, MotionPlusChatterSplitsAsBSquaredOverTotal) {
  // 1 Hz motion (bin 2, leaking into bins 1..3: nothing above 1.75 Hz) plus 40 Hz chatter (bin
  // 80: bins 79..81, i.e. 39.25..40.75 Hz). Any threshold between the two gives b^2 / (a^2 + b^2);
  // one on a tone's bin centre takes half of that bin, which holds 4/6 of the tone.
  const double a = 1.0, b = 0.2;
  const std::vector<Tone> ts = {{2, a, 0.2}, {80, b, 1.3}};
  ASSERT_TRUE(tonesAddUp(ts, kSegment));
  const Eigen::VectorXd x = tones(kN, kSegment, ts);
  const double total = (a * a + b * b) / 2.0;
  // The rounding bound on both integrals, propagated through U / T.
  const double tol = 2.0 * tol::tonesRounding(kSegment, kSegments, a + b) / total;
  const double chatter = b * b / (a * a + b * b);  // 3.8 %
  for (const double f : {1.75, 2.3, 10.0, 25.0, 39.25}) {
    EXPECT_NEAR(varianceFractionAbove(x, kSpectrumFs_Hz, f), chatter, tol) << f << " Hz";
  }
  EXPECT_NEAR(varianceFractionAbove(x, kSpectrumFs_Hz, 1.0), (a * a / 2.0 + b * b) / (a * a + b * b), tol);
  EXPECT_NEAR(varianceFractionAbove(x, kSpectrumFs_Hz, 40.0), chatter / 2.0, tol);
  EXPECT_NEAR(varianceFractionAbove(x, kSpectrumFs_Hz, 40.75), 0.0, tol);
  EXPECT_NEAR(varianceFractionAbove(x, kSpectrumFs_Hz, 499.0), 0.0, tol);
  EXPECT_LT(tol, 1e-11);
}

TEST(SpectrumVarianceFraction, SplitsAStraddlingBinLinearly) {
  // Threshold inside bin 80's band [39.75, 40.25]: the share above moves linearly from all of
  // it to none of it. Bin 80 holds 4/6 of the chatter and bin 81 1/6.
  const double a = 1.0, b = 0.2;
  const Eigen::VectorXd x = tones(kN, kSegment, {{2, a, 0.2}, {80, b, 1.3}});
  const double chatter = b * b / (a * a + b * b);
  const double tol = 2.0 * tol::tonesRounding(kSegment, kSegments, a + b) / ((a * a + b * b) / 2.0);
  for (const double s : {0.0, 0.1, 0.25, 0.6, 1.0}) {
    const double f = 39.75 + 0.5 * s;
    EXPECT_NEAR(varianceFractionAbove(x, kSpectrumFs_Hz, f), chatter * ((1.0 - s) * 4.0 / 6.0 + 1.0 / 6.0), tol)
        << f << " Hz";
  }
}

TEST(SpectrumVarianceFraction, WhiteNoiseIsSplitInProportionToTheBand) {
  // Flat density 2 sigma^2 / fs: E[above] = sigma^2 (fs/2 - f) / (fs/2). The total loses the DC
  // bin (sigma^2 / (3N), its window-weighted share after mean removal) and a sixth of bin 1
  // (mean removal cancels the window's bin-1 component): E[total] = sigma^2 (1 - 4 / (3N)).
  const double sigma = 0.7, df = kSpectrumFs_Hz / static_cast<double>(kSegment);
  const double nyquist = kSpectrumFs_Hz / 2.0;
  const Eigen::VectorXd x = whiteNoise(kN, sigma, 21);
  for (const double f : {10.0, 100.0, 250.0, 450.0}) {
    const double share = (nyquist - f) / nyquist;
    const double expected = share / (1.0 - 4.0 / (3.0 * static_cast<double>(kSegment)));
    const double sd = tol::whiteFractionSd(share, (nyquist - f) / df, f / df - 0.5, kSegments);
    EXPECT_NEAR(varianceFractionAbove(x, kSpectrumFs_Hz, f), expected, tol::kSigmas * sd) << f << " Hz";
  }
}

TEST(SpectrumVarianceFraction, AConstantSignalHasNothingAbove) {
  // 3.7 is not a binary fraction: the segment means round, leaving ~eps-sized residues.
  EXPECT_EQ(varianceFractionAbove(Eigen::VectorXd::Constant(kN, 3.7), kSpectrumFs_Hz, 10.0), 0.0);
  EXPECT_EQ(varianceFractionAbove(Eigen::VectorXd::Zero(kN), kSpectrumFs_Hz, 10.0), 0.0);
}

TEST(SpectrumVarianceFraction, RejectsBadArguments) {
  const Eigen::VectorXd x = whiteNoise(100, 1.0, 4);
  expectInvalidArgumentMentioning([&] { varianceFractionAbove(x, kSpectrumFs_Hz, 600.0); },
                                  "f_hz must be in (0, 500) Hz, got 600");
  expectInvalidArgumentMentioning([&] { varianceFractionAbove(x, kSpectrumFs_Hz, 500.0); }, "got 500");
  expectInvalidArgumentMentioning([&] { varianceFractionAbove(x, kSpectrumFs_Hz, 0.0); }, "got 0");
  expectInvalidArgumentMentioning([&] { varianceFractionAbove(x, kSpectrumFs_Hz, -1.0); }, "got -1");
  expectInvalidArgumentMentioning([&] { varianceFractionAbove(x, kSpectrumFs_Hz, std::nan("")); }, "got nan");
  expectInvalidArgumentMentioning([&] { varianceFractionAbove(x, 0.0, 10.0); },
                                  "sample_rate_hz must be positive and finite, got 0");
  expectInvalidArgumentMentioning([&] { varianceFractionAbove(x.head(5), kSpectrumFs_Hz, 10.0); },
                                  "at least 8 samples, got 5");
  Eigen::VectorXd bad = x;
  bad[42] = std::numeric_limits<double>::infinity();
  expectInvalidArgumentMentioning([&] { varianceFractionAbove(bad, kSpectrumFs_Hz, 10.0); }, "x[42] must be finite, got inf");
  expectInvalidArgumentMentioning([&] { varianceFractionAbove(x, kSpectrumFs_Hz, 10.0, WelchOptions{2.0, 1.5}); },
                                  "'overlap' must be in [0, 1), got 1.5");
}

}  // namespace
}  // namespace exoid::ident
