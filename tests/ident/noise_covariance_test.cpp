// The noise covariance of LS against Monte Carlo: fixed exact states, many seeds of white torque
// noise pushed through the real processing (prepareSignals) and the real estimators; the sample
// std of every parameter must agree with the reported std within a chi-square band.
#include "exoid/ident/estimators/noise_covariance.hpp"

#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/signals/preprocess.hpp"
#include "exoid/ident/estimators/segmental.hpp"
#include "test_support.hpp"

#include <Eigen/LU>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <string>

namespace exoid::ident {
namespace {

constexpr double kSigma = 0.5;  // N m, the reproduce default
constexpr int kDraws = 300;
// Every comparison in this file shares a family-wise false-alarm rate of 1e-3 (Bonferroni over
// at most 60 parameter comparisons): per comparison alpha = 1e-3 / 60.
constexpr double kAlphaEach = 1e-3 / 60.0;

// Standard normal quantile by bisection on erfc (accurate to 1e-12, ample here).
double normalQuantile(double p) {
  double lo = -40.0, hi = 40.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Chi-square quantile with k degrees of freedom (Wilson-Hilferty; relative error < 1e-3 for
// k > 100, far below the band's width of ~20 %).
double chiSquareQuantile(double p, double k) {
  const double z = normalQuantile(p), v = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - v + z * std::sqrt(v), 3);
}

// (n - 1) s^2 / sigma^2 ~ chi^2(n - 1) for Gaussian estimates (LS is linear in Gaussian noise):
// the sample std s over n draws lies in [lo, hi] * sigma with probability 1 - alpha.
void expectStdInBand(const Eigen::MatrixXd& draws, const Eigen::VectorXd& predicted, const std::string& what) {
  const double n = static_cast<double>(draws.cols());
  const double lo = std::sqrt(chiSquareQuantile(0.5 * kAlphaEach, n - 1) / (n - 1));
  const double hi = std::sqrt(chiSquareQuantile(1.0 - 0.5 * kAlphaEach, n - 1) / (n - 1));
  const Eigen::VectorXd mean = draws.rowwise().mean();
  for (Eigen::Index j = 0; j < draws.rows(); ++j) {
    const double sd = std::sqrt((draws.row(j).array() - mean[j]).square().sum() / (n - 1));
    const double ratio = sd / predicted[j];
    EXPECT_GT(ratio, lo) << what << " parameter " << j << ": sample std " << sd << ", predicted " << predicted[j];
    EXPECT_LT(ratio, hi) << what << " parameter " << j << ": sample std " << sd << ", predicted " << predicted[j];
  }
}

// `estimator(d)` on kDraws copies of d with white torque noise on both joints.
Eigen::MatrixXd monteCarlo(const Dataset& d, const std::function<Eigen::VectorXd(const Dataset&)>& estimator,
                           std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> noise(0.0, kSigma);
  Eigen::MatrixXd out;
  for (int k = 0; k < kDraws; ++k) {
    Dataset noisy = d;
    noisy.tau_Nm += Eigen::MatrixX2d::NullaryExpr(d.size(), 2, [&] { return noise(gen); });
    const Eigen::VectorXd x = estimator(noisy);
    if (out.size() == 0) out.resize(x.size(), kDraws);
    out.col(k) = x;
  }
  return out;
}

SignalOptions paperProcessing() { return SignalOptions{}; }  // forward differences, 10 Hz filtfilt, torque filtered
SignalOptions rawProcessing() {
  SignalOptions o;
  o.filter = false;  // recorded derivatives, raw torque
  return o;
}

NoiseChannel channel(const Eigen::MatrixXd& H, const Dataset& d, const SignalOptions& o) {
  return {H, torqueNoisePath(o, 1.0 / d.sampleInterval_s(), d.size()), kSigma};
}

// All 10 parameters from both equations of one record: two independent channels (hip, knee).
void checkStacked(const SignalOptions& o, std::uint64_t seed, const std::string& what) {
  const Dataset d = test::multisineRecord(5.0, true);
  const JointSignals s = prepareSignals(d, o);
  const Eigen::MatrixXd Hh = jointRegressor(s, Joint::kHip, test::kLeg), Hk = jointRegressor(s, Joint::kKnee, test::kLeg);
  const Eigen::VectorXd predicted = stdOf(lsNoiseCovariance({channel(Hh, d, o), channel(Hk, d, o)}));
  const Eigen::MatrixXd draws = monteCarlo(d, [&](const Dataset& noisy) {
    const JointSignals sn = prepareSignals(noisy, o);
    return solveLeastSquares(stackedRegressor(sn, test::kLeg), stackedTorque(sn)).x;
  }, seed);
  expectStdInBand(draws, predicted, what);
}

TEST(NoiseCovariance, RawProcessingStackedMatchesMonteCarlo) { checkStacked(rawProcessing(), 11, "raw, stacked"); }

TEST(NoiseCovariance, PaperProcessingStackedMatchesMonteCarlo) {
  checkStacked(paperProcessing(), 12, "paper, stacked");
}

TEST(NoiseCovariance, FilteredAnglesRawTorqueMatchesMonteCarlo) {
  SignalOptions o;
  o.differentiation = Differentiation::kCentral;
  o.use_recorded_derivatives = false;
  o.filter_torque = false;  // noise reaches the fit white, trimmed only
  checkStacked(o, 13, "central differences, unfiltered torque");
}

TEST(NoiseCovariance, PaperProcessingSegmentalMatchesMonteCarlo) {
  const SignalOptions o = paperProcessing();
  const Dataset knee_rec = test::multisineRecord(5.0, false), both_rec = test::multisineRecord(5.0, true);
  const JointSignals sk = prepareSignals(knee_rec, o), sb = prepareSignals(both_rec, o);
  const test::LinearProblem knee = test::kneeProblem(sk);
  const Eigen::MatrixXd Hh = jointRegressor(sb, Joint::kHip, test::kLeg);
  const Robot leg = twoLinkLeg(test::kLeg);
  const Eigen::VectorXd predicted = stdOf(segmentalNoiseCovariance(
      channel(knee.H, knee_rec, o), channel(Hh.leftCols(5), both_rec, o), Hh.rightCols(5)));
  // Both records get independent noise: draw the knee record's noise, then the hip record's.
  std::mt19937_64 gen(14);
  std::normal_distribution<double> noise(0.0, kSigma);
  MethodOptions mo;
  mo.report_optimality_gap = false;
  Eigen::MatrixXd draws(10, kDraws);
  for (int k = 0; k < kDraws; ++k) {
    Dataset nk = knee_rec, nb = both_rec;
    nk.tau_Nm += Eigen::MatrixX2d::NullaryExpr(nk.size(), 2, [&] { return noise(gen); });
    nb.tau_Nm += Eigen::MatrixX2d::NullaryExpr(nb.size(), 2, [&] { return noise(gen); });
    draws.col(k) = identifySegmental(leg, {{1, recordRows(leg, prepareSignals(nk, o))}, {0, recordRows(leg, prepareSignals(nb, o))}}, Method::kLs, mo).theta;
  }
  expectStdInBand(draws, predicted, "paper, segmental");
}

TEST(NoiseCovariance, UnfilteredPathIsTheCramerRaoBound) {
  // F = trim only: the sandwich collapses to sigma^2 (H^T H)^-1 exactly.
  const Eigen::MatrixXd H = Eigen::MatrixXd::Random(200, 4);
  const Eigen::MatrixXd C = lsNoiseCovariance({{H, rawTorquePath(210, 5), 0.3}});
  const Eigen::MatrixXd expected = 0.09 * (H.transpose() * H).inverse();
  EXPECT_LT((C - expected).norm(), 1e-10 * expected.norm());
}

TEST(NoiseCovariance, FilterPathTransposeMatchesFiltfiltAdjoint) {
  // <F e, h> = <e, F^T h> with F = trimmed filtfilt, for random e and h: the stationary-kernel
  // transpose is exact up to the kernel's value at the trim distance (~1e-6 here), far below
  // 1e-4 relative.
  SignalOptions o;
  const double fs = 1000.0;
  const TorqueNoisePath path = torqueNoisePath(o, fs, 3000);
  std::mt19937_64 gen(5);
  std::normal_distribution<double> n01;
  const Eigen::MatrixXd e = Eigen::MatrixXd::NullaryExpr(3000, 1, [&] { return n01(gen); });
  const Eigen::MatrixXd h = Eigen::MatrixXd::NullaryExpr(path.fittedRows(), 1, [&] { return n01(gen); });
  const Eigen::MatrixXd Fe = filtfilt(*path.filter, e).middleRows(path.trim, path.fittedRows());
  const double lhs = Fe.col(0).dot(h.col(0));
  const double rhs = e.col(0).dot(path.transposeApply(h).col(0));
  EXPECT_NEAR(lhs, rhs, 1e-4 * std::abs(lhs) + 1e-9);
}

TEST(NoiseCovariance, RankDeficientIsInfinite) {
  Eigen::MatrixXd H = Eigen::MatrixXd::Random(100, 3);
  H.col(2) = H.col(0);
  const Eigen::MatrixXd C = lsNoiseCovariance({{H, rawTorquePath(100, 0), 1.0}});
  EXPECT_TRUE(std::isinf(C(0, 0)));
}

TEST(NoiseCovariance, BadChannelsThrow) {
  const Eigen::MatrixXd H = Eigen::MatrixXd::Random(100, 3);
  EXPECT_THROW(lsNoiseCovariance({{H, rawTorquePath(100, 5), 1.0}}), std::invalid_argument);  // rows
  EXPECT_THROW(lsNoiseCovariance({{H, rawTorquePath(100, 0), -1.0}}), std::invalid_argument);
  EXPECT_THROW(lsNoiseCovariance({}), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::ident
