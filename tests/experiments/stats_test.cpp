// Statistics helpers against published and hand-computed values; a table cell's text.
#include "exoid/experiments/report/stats.hpp"

#include "exoid/experiments/report/cells.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace exoid::experiments::stats {
namespace {

// Published tables give 6-7 significant digits: compare to half a unit of the last digit.
TEST(Stats, StudentTQuantileMatchesTables) {
  EXPECT_NEAR(studentTQuantile(0.975, 9), 2.262157, 5e-7);
  EXPECT_NEAR(studentTQuantile(0.975, 1), 12.706205, 5e-7);
  EXPECT_NEAR(studentTQuantile(0.975, 30), 2.042272, 5e-7);
  EXPECT_NEAR(studentTQuantile(0.95, 4), 2.131847, 5e-7);
  EXPECT_NEAR(studentTQuantile(0.025, 9), -2.262157, 5e-7);
  EXPECT_DOUBLE_EQ(studentTQuantile(0.5, 3), 0.0);
}

TEST(Stats, StudentTCdfClosedForms) {
  // df = 1 is Cauchy: F(t) = 1/2 + atan(t)/pi; df = 2: F(t) = 1/2 + t / (2 sqrt(2 + t^2)).
  for (double t : {-3.0, -0.5, 0.0, 0.7, 4.0}) {
    EXPECT_NEAR(studentTCdf(t, 1), 0.5 + std::atan(t) / M_PI, 1e-13) << t;
    EXPECT_NEAR(studentTCdf(t, 2), 0.5 + t / (2.0 * std::sqrt(2.0 + t * t)), 1e-13) << t;
  }
  EXPECT_NEAR(incompleteBeta(3.0, 3.0, 0.5), 0.5, 1e-14);
  EXPECT_THROW(incompleteBeta(-1.0, 1.0, 0.5), std::invalid_argument);
}

TEST(Stats, ConfidenceIntervalOfAKnownSample) {
  // {1..5}: mean 3, s = sqrt(2.5); half-width t(0.975, 4) s / sqrt(5) = 2.7764451 * 0.7071068 = 1.9632432.
  const ConfidenceInterval ci = meanCi({1, 2, 3, 4, 5});
  EXPECT_EQ(ci.n, 5);
  EXPECT_DOUBLE_EQ(ci.mean, 3.0);
  EXPECT_NEAR(ci.std, std::sqrt(2.5), 1e-15);
  EXPECT_NEAR(ci.low, 3.0 - 1.9632432, 5e-7);
  EXPECT_NEAR(ci.high, 3.0 + 1.9632432, 5e-7);
  EXPECT_TRUE(std::isnan(meanCi({1.0}).low));
}

TEST(Stats, WilcoxonExactOnTheHollanderWolfeCase) {
  // Hollander & Wolfe (1973) p. 29, R's wilcox.test example: V = 40, one-sided p = 10/512, so
  // two-sided p = 20/512 = 0.0390625 exactly.
  const std::vector<double> x{1.83, 0.50, 1.62, 2.48, 1.68, 1.88, 1.55, 3.06, 1.30};
  const std::vector<double> y{0.878, 0.647, 0.598, 2.05, 1.06, 1.29, 1.06, 3.14, 1.29};
  const WilcoxonResult r = wilcoxonSignedRank(x, y);
  EXPECT_TRUE(r.exact);
  EXPECT_EQ(r.n_used, 9);
  EXPECT_DOUBLE_EQ(r.w_plus, 40.0);
  EXPECT_DOUBLE_EQ(r.p_value, 20.0 / 512.0);
  // Symmetric: swapping the samples gives W+ = 45 - 40 and the same p.
  const WilcoxonResult s = wilcoxonSignedRank(y, x);
  EXPECT_DOUBLE_EQ(s.w_plus, 5.0);
  EXPECT_DOUBLE_EQ(s.p_value, r.p_value);
}

TEST(Stats, WilcoxonZerosDroppedAndNormalApproximation) {
  // All 30 differences positive and distinct: W+ = 465, mean 232.5, var = 30*31*61/24 = 2363.75;
  // z = (232.5 - 0.5) / sqrt(2363.75) = 4.77187; two-sided p = erfc(z / sqrt 2) = 1.8257e-6.
  std::vector<double> x, y;
  for (int i = 1; i <= 30; ++i) {
    x.push_back(i);
    y.push_back(0.0);
  }
  x.push_back(5.0);  // a zero difference: dropped
  y.push_back(5.0);
  const WilcoxonResult r = wilcoxonSignedRank(x, y);
  EXPECT_FALSE(r.exact);
  EXPECT_EQ(r.n_used, 30);
  EXPECT_DOUBLE_EQ(r.w_plus, 465.0);
  EXPECT_NEAR(r.p_value, std::erfc(232.0 / std::sqrt(2363.75) / std::sqrt(2.0)), 1e-15);
  EXPECT_NEAR(r.p_value, 1.8257e-6, 1e-9);
  EXPECT_THROW(wilcoxonSignedRank({1.0}, {1.0, 2.0}), std::invalid_argument);
}

TEST(Stats, HolmAdjustmentKnownValues) {
  // Holm (1979) by hand: sorted p = 0.01, 0.02, 0.03, 0.04 with m = 4 -> 0.04, 0.06, 0.06, 0.06
  // (running maximum of 0.04, 0.06, 0.06, 0.04); the NaN stays out of the family.
  const std::vector<double> adj = holmAdjust({0.03, 0.01, std::nan(""), 0.04, 0.02});
  EXPECT_NEAR(adj[1], 0.04, 1e-15);
  EXPECT_NEAR(adj[4], 0.06, 1e-15);
  EXPECT_NEAR(adj[0], 0.06, 1e-15);
  EXPECT_NEAR(adj[3], 0.06, 1e-15);
  EXPECT_TRUE(std::isnan(adj[2]));
  EXPECT_EQ(holmAdjust({0.9, 0.8}), (std::vector<double>{1.0, 1.0}));
}

TEST(Stats, MinimalDetectableDifferenceMatchesTheLargeSampleFormula) {
  // For large n the t quantiles tend to the normal ones: (1.959964 + 0.841621) sd / sqrt(n).
  EXPECT_NEAR(minimalDetectableDifference(2.0, 100000), 2.801585 * 2.0 / std::sqrt(100000.0), 1e-5);
  // n = 10: t(0.975, 9) = 2.262157, t(0.8, 9) = 0.883408.
  EXPECT_NEAR(minimalDetectableDifference(1.0, 10), (2.262157 + 0.883408) / std::sqrt(10.0), 1e-5);
  EXPECT_TRUE(std::isnan(minimalDetectableDifference(1.0, 1)));
}


TEST(Stats, CoverageOfAKnownSampleAndItsWilsonInterval) {
  // Errors 0, 1, 3 with sigma 1 (and two pairs without a usable sigma, skipped): |z| <= 1.96 for
  // two of three. Wilson (z = 1.96, n = 3, p = 2/3): centre (p + z^2/6) / (1 + z^2/3), half-width
  // z / (1 + z^2/3) sqrt(p (1 - p) / 3 + z^2 / 36), by hand: [0.2077, 0.9385].
  const stats::Coverage c = stats::coverageOf({0.0, 1.0, 3.0, 5.0, 7.0}, {1.0, 1.0, 1.0, 0.0, NAN});
  EXPECT_EQ(c.n, 3);
  EXPECT_DOUBLE_EQ(c.share, 2.0 / 3.0);
  EXPECT_NEAR(c.low, 0.2077, 5e-5);
  EXPECT_NEAR(c.high, 0.9385, 5e-5);
  EXPECT_DOUBLE_EQ(c.mean_error_over_sigma, 4.0 / 3.0);
  EXPECT_NEAR(c.sd_over_mean_sigma, std::sqrt(7.0 / 3.0), 1e-12);  // sample std of 0, 1, 3
  // All held: the interval reaches 1 and stays inside [0, 1]; none: NaN.
  const stats::Coverage all = stats::coverageOf({0.1, -0.2, 0.3, 0.0}, {1.0, 1.0, 1.0, 1.0});
  EXPECT_EQ(all.share, 1.0);
  EXPECT_EQ(all.high, 1.0);
  EXPECT_NEAR(all.low, 4.0 / (4.0 + 1.959963984540054 * 1.959963984540054), 1e-12);  // n / (n + z^2) when p = 1
  EXPECT_TRUE(std::isnan(stats::coverageOf({}, {}).share));
}

TEST(Stats, HonestSigmasCoverNinetyFivePercentAndABiasIsSeen) {
  // 20000 normal errors of known sigma: the share within 1.96 sigma is 0.95 to its binomial
  // spread (0.0015); shifted by 2 sigma, 0.484 (Phi(-0.04) - Phi(-3.96)), mean error 2 sigma.
  std::mt19937_64 gen(7);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<double> e, biased, s;
  for (int k = 0; k < 20000; ++k) {
    const double sigma = 0.5 + (k % 4);
    const double x = sigma * n(gen);
    e.push_back(x);
    biased.push_back(x + 2.0 * sigma);
    s.push_back(sigma);
  }
  const stats::Coverage honest = stats::coverageOf(e, s), off = stats::coverageOf(biased, s);
  EXPECT_NEAR(honest.share, 0.95, 4 * 0.0015);
  // The Wilson interval about the share: for large n, -+ 1.96 sqrt(p (1 - p) / n).
  const double half = 1.959963984540054 * std::sqrt(honest.share * (1 - honest.share) / 20000.0);
  EXPECT_NEAR(honest.high - honest.low, 2 * half, 1e-3 * half);
  EXPECT_NEAR(0.5 * (honest.low + honest.high), honest.share, 1e-3);
  EXPECT_NEAR(honest.mean_error_over_sigma, 0.0, 4 / std::sqrt(20000.0));
  EXPECT_NEAR(off.share, 0.484, 4 * 0.0036);
  EXPECT_NEAR(off.mean_error_over_sigma, 2.0, 4 / std::sqrt(20000.0));
}

TEST(Stats, MedianOfOddEvenAndEmptySamples) {
  EXPECT_EQ(stats::median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(stats::median({4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_TRUE(std::isnan(stats::median({})));
}

// A table cell: what is not a number is an empty CSV cell and a JSON null; text with a comma,
// quote or line break is one quoted CSV field (RFC 4180).
TEST(TableCells, NonFiniteNumbersAreEmptyOrNullAndFieldsAreQuotedWhenNeeded) {
  EXPECT_EQ(csvNumber(0.1), "0.1");
  EXPECT_EQ(csvNumber(1.0 / 3.0), "0.3333333333");
  EXPECT_EQ(csvNumber(std::nan("")), "");
  EXPECT_EQ(csvNumber(-HUGE_VAL), "");
  EXPECT_TRUE(jsonNumber(std::nan("")).is_null());
  EXPECT_EQ(jsonNumber(2.5).get<double>(), 2.5);
  EXPECT_EQ(csvField("plain text"), "plain text");
  EXPECT_EQ(csvField("a, b"), "\"a, b\"");
  EXPECT_EQ(csvField("say \"no\""), "\"say \"\"no\"\"\"");
  EXPECT_EQ(csvField("two\nlines"), "\"two\nlines\"");
}

}  // namespace
}  // namespace exoid::experiments::stats
