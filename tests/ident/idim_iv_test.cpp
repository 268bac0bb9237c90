// IDIM-IV: the instrumental-variable solve against closed forms (Z = H is least squares; an
// errors-in-variables problem where LS is provably biased and IV is not), the iteration's
// stopping and failure, and the whole method on closed-loop records of the rigid leg: exact on
// exact data, converged in a few iterations on noisy data.
#include "exoid/ident/estimators/idim_iv.hpp"
#include "exoid/ident/estimators/least_squares.hpp"
#include "test_support.hpp"
#include "../support/closed_loop_multisine.hpp"

#include <gtest/gtest.h>

#include <random>

namespace exoid::ident {
namespace {


TEST(InstrumentalVariables, WithTheRegressorAsInstrumentIsLeastSquares) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n01;
  Eigen::MatrixXd H(500, 4);
  Eigen::VectorXd y(500);
  for (Eigen::Index i = 0; i < H.rows(); ++i) {
    for (Eigen::Index j = 0; j < H.cols(); ++j) H(i, j) = n01(rng);
    y[i] = n01(rng);
  }
  const Estimate iv = instrumentalVariables(H, y, H);
  ASSERT_EQ(iv.summary.status, Status::kConverged);
  EXPECT_LT((iv.x - solveLeastSquares(H, y).x).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(InstrumentalVariables, RemoveTheBiasThatANoisyRegressorGivesLeastSquares) {
  // y = a x + b z with the columns measured with noise of variance s2 each: LS converges to
  // x var / (var + s2) (attenuation: here 0.8 of the truth); instruments from the noise-free
  // columns are consistent. N = 20000: the IV standard error is ~1 %, the LS bias 20 %.
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n01;
  const Eigen::Index n = 20000;
  Eigen::MatrixXd H_true(n, 2), H_meas(n, 2);
  Eigen::VectorXd y(n);
  const Eigen::Vector2d x(2.0, -1.0);
  const double s = 0.5;  // noise std; the columns' variance is 1, so var / (var + s^2) = 0.8
  for (Eigen::Index i = 0; i < n; ++i) {
    H_true.row(i) << n01(rng), n01(rng);
    H_meas.row(i) = H_true.row(i) + s * Eigen::RowVector2d(n01(rng), n01(rng));
    y[i] = H_true.row(i).dot(x) + 0.1 * n01(rng);
  }
  const Eigen::VectorXd ls = solveLeastSquares(H_meas, y).x;
  EXPECT_NEAR(ls[0] / x[0], 0.8, 0.03);
  EXPECT_NEAR(ls[1] / x[1], 0.8, 0.03);
  const Estimate iv = instrumentalVariables(H_meas, y, H_true);
  ASSERT_EQ(iv.summary.status, Status::kConverged);
  // IV error std ~ sqrt(x^T S x + 0.01) / sqrt(n) ~ 0.008: 5 of them.
  EXPECT_NEAR(iv.x[0], x[0], 0.04);
  EXPECT_NEAR(iv.x[1], x[1], 0.04);
}

TEST(InstrumentalVariables, InstrumentsBlindToAColumnAreRankDeficient) {
  Eigen::MatrixXd H(100, 2);
  for (Eigen::Index i = 0; i < 100; ++i) H.row(i) << std::sin(0.1 * static_cast<double>(i)), std::cos(0.1 * static_cast<double>(i));
  Eigen::MatrixXd Z = H;
  Z.col(1).setZero();
  EXPECT_EQ(instrumentalVariables(H, H.col(0), Z).summary.status, Status::kRankDeficient);
  test::expectInvalidArgumentMentioning([&] { instrumentalVariables(H, H.col(0), Z.leftCols(1)); }, "Z must match H");
}

TEST(IterateInstrumentalVariables, StopsWhenTheStepIsBelowTheStandardErrorAndReportsFailures) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n01;
  Eigen::MatrixXd H(400, 3);
  Eigen::VectorXd y(400);
  for (Eigen::Index i = 0; i < 400; ++i) {
    H.row(i) << n01(rng), n01(rng), n01(rng);
    y[i] = H.row(i).sum() + 0.1 * n01(rng);
  }
  // Fixed instruments: the first IV solve is the answer, the second step is zero.
  int calls = 0;
  const Estimate e = iterateInstrumentalVariables(H, y, [&](const Eigen::VectorXd&) {
    ++calls;
    return Instruments{true, "", H};
  });
  EXPECT_EQ(e.summary.status, Status::kConverged) << e.summary.message;
  EXPECT_EQ(e.summary.iterations, 1);  // Z = H: the IV solve is the starting LS, step 0
  EXPECT_EQ(calls, 1);
  const Estimate failed = iterateInstrumentalVariables(H, y, [](const Eigen::VectorXd&) {
    return Instruments{false, "the model cannot be simulated", {}};
  });
  EXPECT_EQ(failed.summary.status, Status::kFailed);
  EXPECT_NE(failed.summary.message.find("cannot be simulated"), std::string::npos);
}

SignalOptions parallel() {
  SignalOptions o;
  o.processing = Processing::kParallel;
  return o;
}

// The closed-loop multisine record of the default leg (tests/support/closed_loop_multisine.hpp):
// the measured side simulated with the true parameters under the rig's controller, 8 s at 1 kHz,
// with optional encoder and torque noise.
ClosedLoopRecord closedLoopRecord(bool hip_locked, double noise_q_rad, double noise_tau_Nm, std::uint64_t seed,
                                  bool recorded_derivatives) {
  const test::ClosedLoopMultisine m = test::closedLoopMultisine(8001, test::rigController(hip_locked));
  EXPECT_TRUE(m.run.ok) << m.run.message;
  return test::closedLoopRecordOf(m, test::measuredMultisine(m, {noise_q_rad, noise_tau_Nm, seed}, recorded_derivatives));
}

TEST(IdimIv, IsExactOnExactClosedLoopRecords) {
  const ClosedLoopRecord knee = closedLoopRecord(true, 0, 0, 1, true);
  const ClosedLoopRecord both = closedLoopRecord(false, 0, 0, 2, true);
  const ParamVector truth = toParamVector(defaultLeg());
  const SegmentalResult r = identifySegmentalIv(knee, both, test::kLeg, parallel(), {});
  ASSERT_EQ(r.knee.summary.status, Status::kConverged) << r.knee.summary.message;
  ASSERT_EQ(r.hip.summary.status, Status::kConverged) << r.hip.summary.message;
  // tau = Y x holds exactly at the recorded states: any instruments give the truth, to rounding
  // times conditioning (< 1e3).
  EXPECT_LT(((r.x - truth).cwiseQuotient(truth)).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LE(r.knee.summary.iterations, 2);
  const Estimate all = identifyAllIv(both, test::kLeg, parallel(), {});
  ASSERT_EQ(all.summary.status, Status::kConverged) << all.summary.message;
  EXPECT_LT(((all.x - truth).cwiseQuotient(truth)).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(IdimIv, ConvergesInAFewIterationsOnNoisyRecordsAndStaysWithinItsStandardErrors) {
  // Encoder noise 0.01 deg, torque noise 0.5 N m (exoid's reproduce levels), angles only.
  const ParamVector truth = toParamVector(defaultLeg());
  const ClosedLoopRecord knee = closedLoopRecord(true, 1.745e-4, 0.5, 3, false);
  const ClosedLoopRecord both = closedLoopRecord(false, 1.745e-4, 0.5, 4, false);
  const SegmentalResult r = identifySegmentalIv(knee, both, test::kLeg, parallel(), {});
  ASSERT_EQ(r.knee.summary.status, Status::kConverged) << r.knee.summary.message;
  ASSERT_EQ(r.hip.summary.status, Status::kConverged) << r.hip.summary.message;
  EXPECT_LE(r.knee.summary.iterations, 5);
  EXPECT_LE(r.hip.summary.iterations, 5);
  // The noise is not white after filtering, so no exact band; 10 % of each parameter is ~10x
  // the torque-noise-limited std on these 8 s records.
  EXPECT_LT(((r.x - truth).cwiseQuotient(truth)).cwiseAbs().maxCoeff(), 0.1) << r.x.transpose();
}

TEST(IdimIv, AModelThatCannotBeSimulatedFallsBackToReferenceInstruments) {
  // An iterate with Js < 0 has no positive definite mass matrix: the instruments then come from
  // the reference (perfect tracking), which are as free of measurement noise; the iteration stops
  // there and says so. On exact data the answer is still exact.
  const ClosedLoopRecord both = closedLoopRecord(false, 0, 0, 2, true);
  ParamVector bad = toParamVector(defaultLeg());
  bad[kJs] = -0.2;
  ProcessedRecord instr;
  const Instruments z = instrumentRecord(bad, test::kLeg, both, parallel(), instr);
  ASSERT_TRUE(z.ok);
  EXPECT_TRUE(z.fixed);
  EXPECT_NE(z.message.find("instruments from the reference"), std::string::npos) << z.message;
  EXPECT_NE(z.message.find("not positive definite"), std::string::npos) << z.message;
  EXPECT_EQ(instr.size(), both.measured.size());
  const SegmentalProblem all = bothEquations(both.measured);
  const Estimate e = iterateInstrumentalVariables(all.H, all.y, [&](const Eigen::VectorXd&) {
    Instruments zz = z;
    zz.Z = bothEquations(instr).H;
    return zz;
  });
  ASSERT_EQ(e.summary.status, Status::kConverged) << e.summary.message;
  EXPECT_EQ(e.summary.iterations, 1);
  EXPECT_NE(e.summary.message.find("instruments from the reference"), std::string::npos);
  const ParamVector truth = toParamVector(defaultLeg());
  EXPECT_LT(((e.x - truth).cwiseQuotient(truth)).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(IdimIv, NeedsTheParallelProcessing) {
  const ClosedLoopRecord both = closedLoopRecord(false, 0, 0, 2, true);
  test::expectInvalidArgumentMentioning([&] { identifyAllIv(both, test::kLeg, SignalOptions{}, {}); }, "parallel processing");
  test::expectInvalidArgumentMentioning(
      [&] { estimate(Method::kIdimIv, both.measured.hip, both.measured.tau_Nm.col(0), MethodOptions{}); }, "not a method over y = H x");
  EXPECT_EQ(parseMethod("idim-iv"), Method::kIdimIv);
}

}  // namespace
}  // namespace exoid::ident
