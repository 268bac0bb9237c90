// Tests for signals.hpp. Ground truth: closed forms (Taylor series of finite differences, the
// bilinear-transform Butterworth magnitude and 2nd-order coefficients, impulse responses of
// second-order sections, |H(f)|^2 of a zero-phase filter) and one fixed scipy.signal output.
#include "exoid/ident/signals/signals.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace exoid::ident {
namespace {

using test::expectInvalidArgumentMentioning;

using Complex = std::complex<double>;
constexpr double kPi = 3.14159265358979323846;
constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kFs_Hz = 1000.0;
constexpr double kDt_s = 1.0 / kFs_Hz;
constexpr double kFc_Hz = 10.0;

// ---- Tolerances, in one place -----------------------------------------------------------------
// Roundings are bounded by a small multiple of eps times the size of what is summed; the
// multiples below count the operations involved (rounding each operand and the result).
namespace tol {
// Steady state through the cascade: a few roundings of size eps * |x| per section and step, kept
// alive by the sections' noise gain (sum |h| <~ 100 for these Butterworths), i.e. ~1e-13 |x|.
constexpr double kSteadyStateRel = 1e-12;
// Edge transients of filtfilt decay at least like rho^k (rho = largest pole radius). The
// interior starts where rho^k <= kTransientDecay; the transient started with at most 100x the
// signal amplitude (a generous bound on the modal gains of a <= 6th-order Butterworth), so at
// most 1e-11 x amplitude is left.
constexpr double kTransientDecay = 1e-13;
constexpr double kInteriorRel = 1e-11;
// filtfilt output against scipy's: coefficients agree to ~1e-15 (checked below) and rounding
// over 2 x 64 padded steps of a 100 Hz 3rd-order filter (noise gain < 10) stays below ~1e-13 |x|.
constexpr double kScipyRel = 1e-12;
}  // namespace tol

// ---- Helpers ----------------------------------------------------------------------------------

Eigen::VectorXd timeGrid(Eigen::Index n, double dt_s) {
  return Eigen::VectorXd::LinSpaced(n, 0.0, static_cast<double>(n - 1) * dt_s);
}

// B_s(z) or A_s(z) of section s at z^-1 = w: c0 + c1 w + c2 w^2.
Complex poly(const SosFilter& f, Eigen::Index s, int first, Complex w) {
  return f.sos(s, first) + w * (f.sos(s, first + 1) + w * f.sos(s, first + 2));
}
double l1(const SosFilter& f, Eigen::Index s, int first) {
  return std::abs(f.sos(s, first)) + std::abs(f.sos(s, first + 1)) + std::abs(f.sos(s, first + 2));
}

// H(exp(i 2 pi freq / fs)) evaluated from the sections.
Complex response(const SosFilter& f, double freq_hz, double fs_hz = kFs_Hz) {
  const Complex w = std::polar(1.0, -2.0 * kPi * freq_hz / fs_hz);
  Complex h = 1.0;
  for (Eigen::Index s = 0; s < f.sections(); ++s) h *= poly(f, s, 0, w) / poly(f, s, 3, w);
  return h;
}

// First-order bound on the relative change of |H(freq)| when every coefficient carries a relative
// rounding of eps: sum_s (|b_s|_1 / |B_s| + |a_s|_1 / |A_s|) eps, plus the same at DC for the gain
// that normalises the DC gain, plus 2 eps per section to evaluate it.
double responseRoundingRel(const SosFilter& f, double freq_hz) {
  const Complex w = std::polar(1.0, -2.0 * kPi * freq_hz / kFs_Hz);
  double k = 0.0;
  for (Eigen::Index s = 0; s < f.sections(); ++s) {
    k += l1(f, s, 0) / std::abs(poly(f, s, 0, w)) + l1(f, s, 3) / std::abs(poly(f, s, 3, w)) +
         l1(f, s, 3) / std::abs(poly(f, s, 3, 1.0)) + 2.0;
  }
  return k * kEps;
}

// Largest modulus of the poles, i.e. of the roots of z^2 + a1 z + a2 in any section.
double maxPoleRadius(const SosFilter& f) {
  double rho = 0.0;
  for (Eigen::Index s = 0; s < f.sections(); ++s) {
    const double a1 = f.sos(s, 4), a2 = f.sos(s, 5);
    const Complex root = std::sqrt(Complex(a1 * a1 - 4.0 * a2, 0.0));
    rho = std::max({rho, std::abs((-a1 + root) / 2.0), std::abs((-a1 - root) / 2.0)});
  }
  return rho;
}

// Samples after which a transient decaying like maxPoleRadius^k has shrunk by `decay`.
Eigen::Index settlingSamples(const SosFilter& f, double decay) {
  return static_cast<Eigen::Index>(std::ceil(std::log(decay) / std::log(maxPoleRadius(f))));
}

// Butterworth magnitude through the bilinear transform with prewarping (closed form).
double butterworthMagnitude(int order, double cutoff_hz, double freq_hz) {
  const double ratio = std::tan(kPi * freq_hz / kFs_Hz) / std::tan(kPi * cutoff_hz / kFs_Hz);
  return 1.0 / std::sqrt(1.0 + std::pow(ratio, 2 * order));
}

// ---- differentiate ----------------------------------------------------------------------------

TEST(Differentiate, BothMethodsAreExactOnALine) {
  const double dt_s = 0.01;
  const Eigen::VectorXd t = timeGrid(201, dt_s);
  Eigen::MatrixXd x(t.size(), 2);
  const double slope0 = -1.5, slope1 = 2.0;
  x.col(0) = (0.5 + slope0 * t.array()).matrix();
  x.col(1) = (3.0 + slope1 * t.array()).matrix();
  for (const auto method : {Differentiation::kForward, Differentiation::kCentral, Differentiation::kCentral4}) {
    const Eigen::MatrixXd dx = differentiate(x, dt_s, method);
    ASSERT_EQ(dx.rows(), x.rows());
    ASSERT_EQ(dx.cols(), x.cols());
    for (Eigen::Index c = 0; c < 2; ++c) {
      const double slope = c == 0 ? slope0 : slope1;
      // Samples carry eps |x| each; their difference divided by dt: 2 eps max|x| / dt, plus
      // the subtraction and division (2 eps relative); doubled for the rounding of t.
      const double tol = 4.0 * kEps * x.col(c).cwiseAbs().maxCoeff() / dt_s + 4.0 * kEps * std::abs(slope);
      EXPECT_LE((dx.col(c).array() - slope).abs().maxCoeff(), tol) << "column " << c;
      EXPECT_LT(tol / std::abs(slope), 1e-12);  // the ~1e-12 relative the contract promises
    }
  }
}

TEST(Differentiate, CentralIsExactOnAParabolaInTheInteriorAndForwardIsOffByC2Dt) {
  const double dt_s = 0.01, c0 = 1.0, c1 = -2.0, c2 = 3.0;
  const Eigen::VectorXd t = timeGrid(101, dt_s);
  const Eigen::Index n = t.size();
  const Eigen::MatrixXd x = (c0 + c1 * t.array() + c2 * t.array().square()).matrix();
  const Eigen::ArrayXd exact = c1 + 2.0 * c2 * t.array();
  // As for the line: 4 eps max|x| / dt plus relative roundings of the result.
  const double tol = 4.0 * kEps * x.cwiseAbs().maxCoeff() / dt_s + 8.0 * kEps * exact.abs().maxCoeff();

  const Eigen::MatrixXd central = differentiate(x, dt_s, Differentiation::kCentral);
  EXPECT_LE((central.col(0).array().segment(1, n - 2) - exact.segment(1, n - 2)).abs().maxCoeff(), tol);
  // One-sided ends: (x(dt) - x(0)) / dt = c1 + c2 dt and (x(T) - x(T - dt)) / dt = x'(T) - c2 dt.
  EXPECT_NEAR(central(0, 0), exact(0) + c2 * dt_s, tol);
  EXPECT_NEAR(central(n - 1, 0), exact(n - 1) - c2 * dt_s, tol);

  // Forward: (x(t + dt) - x(t)) / dt = x'(t) + c2 dt exactly for a parabola.
  const Eigen::MatrixXd forward = differentiate(x, dt_s, Differentiation::kForward);
  EXPECT_LE((forward.col(0).array().head(n - 1) - (exact.head(n - 1) + c2 * dt_s)).abs().maxCoeff(), tol);
  EXPECT_NEAR(forward(n - 1, 0), exact(n - 1) - c2 * dt_s, tol);
}

// Largest |error| of d/dt sin(omega t) over rows [first, last).
double sineDerivativeError(double dt_s, Differentiation method, Eigen::Index first,
                           Eigen::Index last_from_end) {
  const double omega = 2.0 * kPi;  // 1 Hz
  const Eigen::VectorXd t = timeGrid(static_cast<Eigen::Index>(std::lround(2.0 / dt_s)) + 1, dt_s);
  const Eigen::MatrixXd x = (omega * t.array()).sin().matrix();
  const Eigen::ArrayXd exact = omega * (omega * t.array()).cos();
  const Eigen::ArrayXd error = differentiate(x, dt_s, method).col(0).array() - exact;
  return error.segment(first, t.size() - first - last_from_end).abs().maxCoeff();
}

TEST(Differentiate, ErrorIsFirstOrderForForwardAndSecondOrderForCentral) {
  const double omega = 2.0 * kPi, dt_s = 0.01;
  // Taylor: forward error = dt/2 x'' + dt^2/6 x''' + ..., central = dt^2/6 x''' + O(dt^4). The
  // leading terms give exactly 2 and 4 when dt halves; the next terms and the sampling of the
  // maximum on the grid change the maxima by <= (omega dt)^2 / 8 = 5e-4 relative, so 1% bounds.
  const double fwd = sineDerivativeError(dt_s, Differentiation::kForward, 0, 0);
  const double fwd_half = sineDerivativeError(dt_s / 2, Differentiation::kForward, 0, 0);
  EXPECT_NEAR(fwd / fwd_half, 2.0, 0.02);
  EXPECT_NEAR(fwd, dt_s / 2 * omega * omega, 0.01 * fwd);
  // Central: one-sided ends excluded (they are first order).
  const double cen = sineDerivativeError(dt_s, Differentiation::kCentral, 1, 1);
  const double cen_half = sineDerivativeError(dt_s / 2, Differentiation::kCentral, 1, 1);
  EXPECT_NEAR(cen / cen_half, 4.0, 0.04);
  EXPECT_NEAR(cen, dt_s * dt_s / 6 * omega * omega * omega, 0.01 * cen);
}

TEST(Differentiate, FivePointIsExactOnAQuarticInTheInteriorAndFourthOrderOnASine) {
  // The five-point stencil differentiates polynomials up to degree 4 exactly: interior error is
  // rounding only (the stencil's weights sum to 18/12 of |x| / dt: 36 eps max|x| / (12 dt) plus
  // relative rounding of the result, doubled).
  const double dt_s = 0.01;
  const Eigen::VectorXd t = timeGrid(101, dt_s);
  const Eigen::Index n = t.size();
  const Eigen::ArrayXd ta = t.array();
  const Eigen::MatrixXd x = (1.0 - 2.0 * ta + 3.0 * ta.square() - 0.5 * ta.cube() + 0.25 * ta.pow(4)).matrix();
  const Eigen::ArrayXd exact = -2.0 + 6.0 * ta - 1.5 * ta.square() + ta.cube();
  const double tol = 2.0 * (36.0 * kEps * x.cwiseAbs().maxCoeff() / (12.0 * dt_s) + 8.0 * kEps * exact.abs().maxCoeff());
  const Eigen::MatrixXd d4 = differentiate(x, dt_s, Differentiation::kCentral4);
  EXPECT_LE((d4.col(0).array().segment(2, n - 4) - exact.segment(2, n - 4)).abs().maxCoeff(), tol);
  // On sin(omega t): leading error (omega dt)^4 / 30 times omega; halving dt divides it by 16.
  // Two samples at each end use lower orders and are excluded. Next terms and the grid sampling
  // of the maximum: <= (omega dt)^2 relative, 4e-3 here, so 2 % bounds.
  const double omega = 2.0 * kPi;
  const double e = sineDerivativeError(dt_s, Differentiation::kCentral4, 2, 2);
  const double e_half = sineDerivativeError(dt_s / 2, Differentiation::kCentral4, 2, 2);
  EXPECT_NEAR(e, std::pow(omega * dt_s, 4) / 30.0 * omega, 0.02 * e);
  EXPECT_NEAR(e / e_half, 16.0, 0.32);
  EXPECT_STREQ(toString(Differentiation::kCentral4), "central4");
}

TEST(Differentiate, RejectsBadArguments) {
  const Eigen::MatrixXd x = Eigen::MatrixXd::Ones(5, 2);
  expectInvalidArgumentMentioning(
      [] { differentiate(Eigen::MatrixXd::Ones(1, 2), 0.1, Differentiation::kForward); }, "got 1");
  expectInvalidArgumentMentioning([&] { differentiate(x, 0.0, Differentiation::kForward); },
                                  "dt_s must be positive and finite, got 0");
  expectInvalidArgumentMentioning([&] { differentiate(x, -0.5, Differentiation::kCentral); }, "got -0.5");
  expectInvalidArgumentMentioning([&] { differentiate(x, std::nan(""), Differentiation::kCentral); },
                                  "got nan");
}

// ---- butterworthLowpass -----------------------------------------------------------------------

TEST(ButterworthLowpass, SecondOrderMatchesTheBilinearClosedForm) {
  const SosFilter f = butterworthLowpass(2, kFc_Hz, kFs_Hz);
  ASSERT_EQ(f.sections(), 1);
  const double k = std::tan(kPi * kFc_Hz / kFs_Hz), r2 = std::sqrt(2.0);
  const double norm = 1.0 + r2 * k + k * k;
  const double b0 = k * k / norm;
  const double expected[6] = {b0, 2 * b0, b0, 1.0, 2.0 * (k * k - 1.0) / norm, (1.0 - r2 * k + k * k) / norm};
  // a: |a| <= 2 from ~8 roundings on either side -> 8 eps |a|. b: the gain normalises the DC
  // gain with 1 + a1 + a2, which cancels: relative error 8 eps |a|_1 / |1 + a1 + a2|.
  const double b_rel = 8.0 * kEps * l1(f, 0, 3) / std::abs(1.0 + f.sos(0, 4) + f.sos(0, 5));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(f.sos(0, i), expected[i], b_rel * expected[i]) << "b" << i;
  EXPECT_EQ(f.sos(0, 3), 1.0);
  for (int i = 4; i < 6; ++i) EXPECT_NEAR(f.sos(0, i), expected[i], 8.0 * kEps * 2.0) << "a" << i - 3;
}

// scipy.signal.butter(order, cutoff_hz, fs=1000, output='sos'), scipy 1.10.1.
struct ScipyButter {
  int order;
  double cutoff_hz;
  std::vector<std::vector<double>> sos;
};
const std::vector<ScipyButter>& scipyButter() {
  static const std::vector<ScipyButter> cases = {
      {4,
       10.0,
       {{8.9848614639706458e-07, 1.7969722927941292e-06, 8.9848614639706458e-07, 1, -1.8866095826215064,
         0.89033973628402419},
        {1, 2, 1, 1, -1.9492159580258417, 0.95306989532789088}}},
      // Odd orders: scipy pairs the extra zero at 0 with the pole nearest to it.
      {5,
       10.0,
       {{2.7688714124013037e-08, 5.5377428248026074e-08, 2.7688714124013037e-08, 1, -0.93906250581749229, 0},
        {1, 2, 1, 1, -1.899558547017649, 0.90331430302387017},
        {1, 1, 0, 1, -1.9580605469826651, 0.96193197156782495}}},
      {3,
       400.0,
       {{0.52762438250194321, 0.52762438250194321, 0, 1, 0.50952544949442879, 0},
        {1, 2, 1, 1, 1.2505164308487398, 0.54572331550945752}}},
  };
  return cases;
}

TEST(ButterworthLowpass, MatchesScipyIncludingSectionPairing) {
  for (const auto& c : scipyButter()) {
    const SosFilter f = butterworthLowpass(c.order, c.cutoff_hz, kFs_Hz);
    ASSERT_EQ(f.sections(), static_cast<Eigen::Index>(c.sos.size())) << "order " << c.order;
    // scipy computes the gain from the analog poles, we from the DC gain of the stored
    // coefficients: they differ by the cancellation in the sections' 1 + a1 + a2 (see above).
    double gain_rel = 0.0;
    for (Eigen::Index s = 0; s < f.sections(); ++s) {
      gain_rel += 8.0 * kEps * l1(f, s, 3) / std::abs(1.0 + f.sos(s, 4) + f.sos(s, 5));
    }
    for (Eigen::Index s = 0; s < f.sections(); ++s) {
      for (int i = 0; i < 6; ++i) {
        const double expected = c.sos[static_cast<std::size_t>(s)][static_cast<std::size_t>(i)];
        const double tol = (s == 0 && i < 3) ? gain_rel * std::abs(expected)
                                             : 8.0 * kEps * std::max(1.0, std::abs(expected));
        EXPECT_NEAR(f.sos(s, i), expected, tol)
            << "order " << c.order << " fc " << c.cutoff_hz << " sos(" << s << ", " << i << ")";
      }
    }
  }
}

const int kOrders[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
const double kCutoffs_Hz[] = {10.0, 100.0, 250.0, 400.0};

TEST(ButterworthLowpass, DcGainIsOne) {
  for (const int order : kOrders) {
    for (const double fc : {1.0, 10.0, 100.0, 250.0, 400.0, 499.0}) {
      const SosFilter f = butterworthLowpass(order, fc, kFs_Hz);
      EXPECT_EQ(f.sections(), (order + 1) / 2);
      // Evaluating H(1) sums the coefficients in another order than the design: the rounding
      // bound of the response at DC.
      EXPECT_NEAR(std::abs(response(f, 0.0) - 1.0), 0.0, responseRoundingRel(f, 0.0))
          << "order " << order << " fc " << fc;
    }
  }
}

TEST(ButterworthLowpass, MagnitudeIsTheClosedFormAndHalfPowerAtTheCutoff) {
  for (const int order : kOrders) {
    for (const double fc : kCutoffs_Hz) {
      const SosFilter f = butterworthLowpass(order, fc, kFs_Hz);
      // |H| = 1/sqrt(2) at the cutoff. The coefficient rounding bound is below 1e-12 on this
      // grid except for orders >= 7 at 10 Hz, whose sections have poles within ~1e-3 of the
      // unit circle near the cutoff; there the bound itself is the tolerance.
      const double at_cutoff = std::abs(response(f, fc));
      const double cutoff_tol = std::max(1e-12, responseRoundingRel(f, fc) / std::sqrt(2.0));
      EXPECT_NEAR(at_cutoff, 1.0 / std::sqrt(2.0), cutoff_tol) << "order " << order << " fc " << fc;
      if (order <= 6) {
        EXPECT_LE(cutoff_tol, 1e-12) << "order " << order << " fc " << fc;
      }
      for (int k = 0; k < 200; ++k) {
        const double freq = (k + 0.5) / 200.0 * kFs_Hz / 2.0;
        const double expected = butterworthMagnitude(order, fc, freq);
        // Coefficient rounding plus ~4 N eps for the closed form's power and root.
        const double rel = responseRoundingRel(f, freq) + 4.0 * order * kEps;
        EXPECT_NEAR(std::abs(response(f, freq)), expected, rel * expected)
            << "order " << order << " fc " << fc << " at " << freq << " Hz";
      }
    }
  }
}

TEST(ButterworthLowpass, MagnitudeDecreasesMonotonically) {
  for (const int order : kOrders) {
    for (const double fc : kCutoffs_Hz) {
      const SosFilter f = butterworthLowpass(order, fc, kFs_Hz);
      double previous = std::abs(response(f, 0.0));
      for (int k = 1; k <= 2000; ++k) {
        const double freq = k / 2000.0 * kFs_Hz / 2.0;
        const double now = std::abs(response(f, freq));
        // Flat regions differ only by rounding: allow the rounding bound at this frequency.
        EXPECT_LE(now, previous + responseRoundingRel(f, freq) * previous)
            << "order " << order << " fc " << fc << " at " << freq << " Hz";
        previous = now;
      }
      EXPECT_LT(previous, 1e-12);  // B(z) has its zeros at z = -1, i.e. at Nyquist
    }
  }
}

TEST(ButterworthLowpass, RejectsBadArguments) {
  expectInvalidArgumentMentioning([] { butterworthLowpass(0, 10.0, 1000.0); },
                                  "order must be in [1, 12], got 0");
  expectInvalidArgumentMentioning([] { butterworthLowpass(13, 10.0, 1000.0); }, "got 13");
  expectInvalidArgumentMentioning([] { butterworthLowpass(2, 600.0, 1000.0); },
                                  "cutoff_hz must be in (0, 500) Hz, got 600");
  expectInvalidArgumentMentioning([] { butterworthLowpass(2, 500.0, 1000.0); }, "got 500");
  expectInvalidArgumentMentioning([] { butterworthLowpass(2, 0.0, 1000.0); }, "got 0");
  expectInvalidArgumentMentioning([] { butterworthLowpass(2, -3.0, 1000.0); }, "got -3");
  expectInvalidArgumentMentioning([] { butterworthLowpass(2, std::nan(""), 1000.0); }, "got nan");
  expectInvalidArgumentMentioning([] { butterworthLowpass(2, 10.0, 0.0); },
                                  "sample_rate_hz must be positive and finite, got 0");
  expectInvalidArgumentMentioning(
      [] { butterworthLowpass(2, 10.0, std::numeric_limits<double>::infinity()); }, "got inf");
}

// ---- sosfilt ----------------------------------------------------------------------------------

TEST(Sosfilt, ImpulseResponseOfACascadeIsTheClosedForm) {
  // Section 1: poles rho exp(+-i theta): 1 / A(z) has h[n] = rho^n sin((n + 1) theta) / sin(theta).
  // Section 2: one pole r: h[n] = r^n. Numerators shift and weight them; the cascade convolves.
  const double rho = 0.95, theta = 0.3, r = -0.8;
  const double b[3] = {0.2, -0.1, 0.4}, c0 = 0.5, c1 = 0.25;
  SosFilter f;
  f.sos.resize(2, 6);
  f.sos.row(0) << b[0], b[1], b[2], 1.0, -2.0 * rho * std::cos(theta), rho * rho;
  f.sos.row(1) << c0, c1, 0.0, 1.0, -r, 0.0;
  const Eigen::Index n = 300;
  const auto g = [&](Eigen::Index k) {
    const double kd = static_cast<double>(k);
    return k < 0 ? 0.0 : std::pow(rho, kd) * std::sin((kd + 1.0) * theta) / std::sin(theta);
  };
  const auto p = [&](Eigen::Index k) { return k < 0 ? 0.0 : std::pow(r, static_cast<double>(k)); };
  std::vector<double> h1(n), h(n, 0.0);
  for (Eigen::Index k = 0; k < n; ++k) h1[k] = b[0] * g(k) + b[1] * g(k - 1) + b[2] * g(k - 2);
  for (Eigen::Index k = 0; k < n; ++k) {
    for (Eigen::Index j = 0; j <= k; ++j) h[k] += h1[j] * (c0 * p(k - j) + c1 * p(k - j - 1));
  }
  Eigen::MatrixXd impulse = Eigen::MatrixXd::Zero(n, 1);
  impulse(0, 0) = 1.0;
  const Eigen::MatrixXd y = sosfilt(f, impulse);
  // Roundings of eps |h| per step, amplified by the sum of |impulse response| of the sections
  // (<= 1 / (1 - rho)^2 = 400 and 1 / (1 - |r|) = 5); the closed form is accurate to ~n eps.
  const double tol = 8.0 * kEps * (400.0 * 5.0 + static_cast<double>(n)) * y.cwiseAbs().maxCoeff();
  for (Eigen::Index k = 0; k < n; ++k) EXPECT_NEAR(y(k, 0), h[k], tol) << "sample " << k;
}

TEST(Sosfilt, SinusoidInSteadyStateHasTheGainAndPhaseOfH) {
  const SosFilter f = butterworthLowpass(4, kFc_Hz, kFs_Hz);
  const double freq = 5.0;
  const Eigen::VectorXd t = timeGrid(4000, kDt_s);
  const Eigen::MatrixXd x = (2.0 * kPi * freq * t.array()).sin().matrix();
  const Eigen::MatrixXd y = sosfilt(f, x);
  const Complex h = response(f, freq);
  const Eigen::ArrayXd expected = std::abs(h) * (2.0 * kPi * freq * t.array() + std::arg(h)).sin();
  const Eigen::Index settled = settlingSamples(f, tol::kTransientDecay);
  ASSERT_LT(settled, t.size() / 2);
  EXPECT_LE((y.col(0).array() - expected).tail(t.size() - settled).abs().maxCoeff(), tol::kInteriorRel);
}

TEST(Sosfilt, ColumnsAreFilteredIndependently) {
  const SosFilter f = butterworthLowpass(3, 50.0, kFs_Hz);
  Eigen::MatrixXd x(500, 7);  // more columns than one SIMD block
  for (Eigen::Index c = 0; c < x.cols(); ++c) {
    for (Eigen::Index i = 0; i < x.rows(); ++i)
      x(i, c) = std::sin(0.01 * static_cast<double>((c + 1) * i)) + static_cast<double>(c);
  }
  const Eigen::MatrixXd y = sosfilt(f, x);
  for (Eigen::Index c = 0; c < x.cols(); ++c) EXPECT_EQ(sosfilt(f, x.col(c)), y.col(c)) << "column " << c;
}

TEST(Sosfilt, RejectsInvalidSections) {
  const Eigen::MatrixXd x = Eigen::MatrixXd::Ones(100, 1);
  expectInvalidArgumentMentioning([&] { sosfilt(SosFilter{}, x); }, "got 0");
  SosFilter f = butterworthLowpass(2, kFc_Hz, kFs_Hz);
  f.sos(0, 3) = 2.0;
  expectInvalidArgumentMentioning([&] { sosfilt(f, x); }, "must be 1, got 2");
  expectInvalidArgumentMentioning([&] { filtfilt(f, x); }, "must be 1, got 2");
  f.sos(0, 3) = 1.0;
  f.sos(0, 5) = std::nan("");
  expectInvalidArgumentMentioning([&] { sosfilt(f, x); }, "sos(0, 5) must be finite, got nan");
  // A pole at z = 1 has no steady state to start filtfilt from.
  f.sos.row(0) << 1.0, 0.0, 0.0, 1.0, -1.0, 0.0;
  expectInvalidArgumentMentioning([&] { filtfilt(f, x); }, "pole at z = 1");
}

// ---- filtfilt ---------------------------------------------------------------------------------

class FiltfiltOrder : public ::testing::TestWithParam<int> {
 protected:
  SosFilter f_ = butterworthLowpass(GetParam(), kFc_Hz, kFs_Hz);
  Eigen::Index settled_ = settlingSamples(f_, tol::kTransientDecay);
  Eigen::VectorXd t_ = timeGrid(10000, kDt_s);  // 10 s
  Eigen::Index n_ = t_.size();
  Eigen::Index interior_ = n_ - 2 * settled_;
};

TEST_P(FiltfiltOrder, ConstantComesBackUnchangedIncludingTheEdges) {
  // DC gain 1, and the steady-state initial conditions leave no edge transient.
  const Eigen::Index padlen = 3 * (2 * f_.sections() + 1 - GetParam() % 2);
  for (const Eigen::Index n : {padlen + 1, n_}) {
    Eigen::MatrixXd x(n, 2);
    x.col(0).setConstant(3.7);
    x.col(1).setConstant(-1.2);
    const Eigen::MatrixXd y = filtfilt(f_, x);
    EXPECT_LE((y - x).cwiseAbs().maxCoeff(), tol::kSteadyStateRel * 3.7) << n << " samples";
  }
}

TEST_P(FiltfiltOrder, RampComesBackUnchangedInTheInterior) {
  // The odd extension of a ramp is a ramp; a zero-phase filter with DC gain 1 passes it.
  const Eigen::MatrixXd x = (2.0 + 0.5 * t_.array()).matrix();
  ASSERT_GT(interior_, n_ / 2);
  const Eigen::MatrixXd y = filtfilt(f_, x);
  EXPECT_LE((y - x).middleRows(settled_, interior_).cwiseAbs().maxCoeff(),
            tol::kInteriorRel * x.cwiseAbs().maxCoeff());
}

TEST_P(FiltfiltOrder, SinusoidsBelowTheCutoffComeBackInPhaseScaledByHSquared) {
  // 1 Hz (|H|^2 = 1 - O((1/10)^(2N))) and 8 Hz, near the cutoff, where |H|^2 and |H| differ by
  // more than 1e-2: a single pass or a missing pass would fail by far.
  const double freqs[2] = {1.0, 8.0}, phase = 0.3;
  Eigen::MatrixXd x(n_, 2), expected(n_, 2);
  for (int c = 0; c < 2; ++c) {
    x.col(c) = (2.0 * kPi * freqs[c] * t_.array() + phase).sin().matrix();
    const double gain = std::norm(response(f_, freqs[c]));  // |H|^2
    expected.col(c) = gain * x.col(c);
    if (c == 1) {
      EXPECT_GT(std::abs(gain - std::sqrt(gain)), 1e-2);
    }
  }
  const Eigen::MatrixXd y = filtfilt(f_, x);
  EXPECT_LE((y - expected).middleRows(settled_, interior_).cwiseAbs().maxCoeff(), tol::kInteriorRel);
}

TEST_P(FiltfiltOrder, HundredHzComponentIsAttenuatedByHSquared) {
  const Eigen::ArrayXd slow = (2.0 * kPi * 1.0 * t_.array()).sin();
  const Eigen::ArrayXd fast = 0.5 * (2.0 * kPi * 100.0 * t_.array() + 0.7).sin();
  const Eigen::MatrixXd x = (slow + fast).matrix();
  const Eigen::ArrayXd expected = std::norm(response(f_, 1.0)) * slow + std::norm(response(f_, 100.0)) * fast;
  const Eigen::MatrixXd y = filtfilt(f_, x);
  EXPECT_LE((y.col(0).array() - expected).segment(settled_, interior_).abs().maxCoeff(), tol::kInteriorRel);
}

INSTANTIATE_TEST_SUITE_P(Orders1To6, FiltfiltOrder, ::testing::Range(1, 7));

// Lag in [-max_lag, max_lag] maximising the normalised correlation of y[i] with x[i + lag] over
// rows [first, first + count); a delayed copy y[i] = x[i - d] peaks at lag = -d.
Eigen::Index peakCorrelationLag(const Eigen::VectorXd& y, const Eigen::VectorXd& x, Eigen::Index first,
                                Eigen::Index count, Eigen::Index max_lag) {
  Eigen::Index best_lag = 0;
  double best = -2.0;
  for (Eigen::Index lag = -max_lag; lag <= max_lag; ++lag) {
    double yx = 0.0, yy = 0.0, xx = 0.0;  // plain sums: Eigen's AVX-512 dot trips GCC 12's -Wuninitialized
    for (Eigen::Index i = first; i < first + count; ++i) {
      yx += y[i] * x[i + lag];
      yy += y[i] * y[i];
      xx += x[i + lag] * x[i + lag];
    }
    const double corr = yx / std::sqrt(yy * xx);
    if (corr > best) {
      best = corr;
      best_lag = lag;
    }
  }
  return best_lag;
}

TEST(Filtfilt, CrossCorrelationPeaksAtLagZeroWhereSosfiltLags) {
  const SosFilter f = butterworthLowpass(4, kFc_Hz, kFs_Hz);
  const Eigen::VectorXd t = timeGrid(10000, kDt_s);
  const Eigen::ArrayXd w = 2.0 * kPi * t.array();
  const Eigen::VectorXd x =
      ((0.5 * w).sin() + 0.7 * (1.3 * w + 0.4).cos() + 0.4 * (2.9 * w + 1.1).sin()).matrix();
  const Eigen::Index first = 1000, count = 8000, max_lag = 100;
  EXPECT_EQ(peakCorrelationLag(filtfilt(f, x), x, first, count, max_lag), 0);
  // The causal pass lags by its group delay (~42 samples for this filter near DC).
  EXPECT_GT(peakCorrelationLag(sosfilt(f, x), x, first, count, max_lag), -max_lag);
  EXPECT_LT(peakCorrelationLag(sosfilt(f, x), x, first, count, max_lag), -20);
}

TEST(Filtfilt, ImpulseResponseIsSymmetricWithUnitArea) {
  const SosFilter f = butterworthLowpass(4, kFc_Hz, kFs_Hz);
  const Eigen::Index n = 10001, centre = 5000;
  ASSERT_LT(settlingSamples(f, 1e-30), centre);  // the edges do not reach the centre
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(n, 1);
  x(centre, 0) = 1.0;
  const Eigen::MatrixXd y = filtfilt(f, x);
  Eigen::Index peak = 0;
  const double top = y.col(0).maxCoeff(&peak);
  EXPECT_EQ(peak, centre);
  // The two halves come from different rounding paths: eps |y| per step times the noise gain.
  for (Eigen::Index k = 1; k < centre; ++k)
    EXPECT_NEAR(y(centre + k, 0), y(centre - k, 0), tol::kSteadyStateRel * top) << k;
  // Area = H(1)^2 = 1: n roundings of eps |y|.
  EXPECT_NEAR(y.sum(), 1.0, static_cast<double>(n) * kEps);
}

TEST(Filtfilt, MatchesScipySosfiltfiltOnAFixedInput) {
  // scipy 1.10.1: sosfiltfilt(butter(3, 100, fs=1000, output='sos'), x) with
  // x[i] = ((37 i) % 23) / 23 - 0.5 + 0.05 i, i = 0..39 (odd order: padlen 12, not 15).
  const double expected[40] = {
      -0.49784636122925441, -0.26509559182659753, -0.064345354760331763, 0.085582344872911428,
      0.18471419086604618,  0.24748618425956104,  0.29211051985410685,   0.33170444366411522,
      0.37263388224027966,  0.41807996414982729,  0.47061516888356625,   0.53101662085672963,
      0.59668727270870248,  0.66348314773250583,  0.72930494338342433,   0.79461286074865511,
      0.85871466769070159,  0.91657884314917093,  0.96082816219044209,   0.98741570482065122,
      0.99940021390553557,  1.0059068542806766,   1.0182518427316019,    1.0455894143412205,
      1.0909656662515135,   1.1501655661376891,   1.2153858210201969,    1.280893669485522,
      1.3451648945452455,   1.4080497552677971,   1.4675952118447579,    1.5211314459355119,
      1.5691941622366388,   1.6170677558322615,   1.671963169755406,     1.7395287010814153,
      1.8234772651935423,   1.9267084358400115,   2.0496363632857388,    2.186118575294592};
  Eigen::MatrixXd x(40, 1);
  for (int i = 0; i < 40; ++i) x(i, 0) = static_cast<double>((37 * i) % 23) / 23.0 - 0.5 + 0.05 * i;
  const Eigen::MatrixXd y = filtfilt(butterworthLowpass(3, 100.0, kFs_Hz), x);
  for (int i = 0; i < 40; ++i)
    EXPECT_NEAR(y(i, 0), expected[i], tol::kScipyRel * x.cwiseAbs().maxCoeff()) << "sample " << i;
}

TEST(Filtfilt, ColumnsAreFilteredIndependently) {
  const SosFilter f = butterworthLowpass(4, kFc_Hz, kFs_Hz);
  Eigen::MatrixXd x(300, 6);  // more columns than one SIMD block
  for (Eigen::Index c = 0; c < x.cols(); ++c) {
    for (Eigen::Index i = 0; i < x.rows(); ++i)
      x(i, c) = std::cos(0.02 * static_cast<double>((c + 2) * i)) - static_cast<double>(c);
  }
  const Eigen::MatrixXd y = filtfilt(f, x);
  for (Eigen::Index c = 0; c < x.cols(); ++c) EXPECT_EQ(filtfilt(f, x.col(c)), y.col(c)) << "column " << c;
}

TEST(Filtfilt, ZeroAndRepeatedColumnsComeOutAsIfFilteredAlone) {
  // filtfilt filters only the distinct non-zero columns (a regressor's structural zeros and
  // repeats) and copies the rest: the output must be what filtering each column alone gives, bit
  // for bit, in any order of zeros, repeats and columns that differ in one sample only.
  const SosFilter f = butterworthLowpass(2, kFc_Hz, kFs_Hz);
  Eigen::MatrixXd x(400, 9);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    x(i, 0) = 0.0;
    x(i, 1) = std::sin(0.03 * static_cast<double>(i));
    x(i, 2) = x(i, 1);
    x(i, 3) = std::cos(0.05 * static_cast<double>(i));
    x(i, 4) = 0.0;
    x(i, 5) = x(i, 3);
    x(i, 6) = x(i, 1);
    x(i, 7) = x(i, 3);
    x(i, 8) = x(i, 1);
  }
  x(399, 7) += 1e-12;  // not a repeat: differs in the last sample only
  x(0, 8) = 0.0;       // nor this one: differs in the first
  const Eigen::MatrixXd y = filtfilt(f, x);
  for (Eigen::Index c = 0; c < x.cols(); ++c) EXPECT_EQ(filtfilt(f, x.col(c)), y.col(c)) << "column " << c;
  EXPECT_TRUE((y.col(0).array() == 0.0).all());
}

TEST(Filtfilt, RejectsSignalsNotLongerThanPadlen) {
  // Even order 4: 2 sections, padlen 3 * 5 = 15. Odd order 3: one section has b2 = 0 and one
  // a2 = 0, so scipy's padlen is 3 * (5 - 1) = 12 (as scipy 1.10.1 reports).
  const SosFilter even = butterworthLowpass(4, kFc_Hz, kFs_Hz);
  expectInvalidArgumentMentioning([&] { filtfilt(even, Eigen::MatrixXd::Ones(15, 2)); },
                                  "padlen = 15 for 2 sections, got 15");
  EXPECT_NO_THROW(filtfilt(even, Eigen::MatrixXd::Ones(16, 2)));
  const SosFilter odd = butterworthLowpass(3, kFc_Hz, kFs_Hz);
  expectInvalidArgumentMentioning([&] { filtfilt(odd, Eigen::MatrixXd::Ones(12, 1)); },
                                  "padlen = 12 for 2 sections, got 12");
  EXPECT_NO_THROW(filtfilt(odd, Eigen::MatrixXd::Ones(13, 1)));
}

}  // namespace
}  // namespace exoid::ident
