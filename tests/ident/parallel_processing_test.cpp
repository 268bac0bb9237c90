// Parallel filtering and decimation (Processing::kParallel): exact data give the exact
// parameters whatever the filter, with recorded derivatives or with angles alone; noisy data
// scatter as the noise covariance of the same processing says; the paper's processing does not
// have the first property (the review measured up to 38 % on exact data).
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/estimators/noise_covariance.hpp"
#include "exoid/ident/signals/preprocess.hpp"
#include "exoid/ident/estimators/segmental.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace exoid::ident {
namespace {


SignalOptions parallel() {
  SignalOptions o;
  o.processing = Processing::kParallel;
  return o;
}

Eigen::VectorXd stackedLs(const ProcessedRecord& r) {
  Eigen::MatrixXd H(2 * r.size(), kNumParams);
  H << r.hip, r.knee;
  Eigen::VectorXd y(2 * r.size());
  y << r.tau_Nm.col(0), r.tau_Nm.col(1);
  return solveLeastSquares(H, y).x;
}

double maxRelError(const Eigen::VectorXd& x, const ParamVector& truth) {
  return ((x - truth).cwiseQuotient(truth.cwiseAbs())).cwiseAbs().maxCoeff();
}

TEST(ParallelProcessing, ExactDataGiveExactParametersWithRecordedDerivatives) {
  // filter(tau) = filter(Y) x exactly: only rounding, amplified by the condition number (~1e3).
  const ParamVector truth = toParamVector(defaultLeg());
  const ProcessedRecord r = processRecord(test::multisineRecord(10.0, true, true), test::kLeg, parallel());
  EXPECT_EQ(r.size(), (10000 - 2 * 300 + 19) / 20);  // trimmed 0.3 s each end, every 20th row
  EXPECT_LT(maxRelError(stackedLs(r), truth), 1e-8);
}

TEST(ParallelProcessing, ExactDataGiveExactParametersFromAnglesAlone) {
  // Angles only: five-point derivatives of the pre-filtered angles, error (w dt)^4 / 30 <= 3e-9
  // relative at the 1.9 Hz harmonic, pre-filter gain loss (1.9 / 50)^8 = 4e-12: far below the
  // 1e-6 promised. Precondition: no sample within the derivative error of zero velocity, where
  // sgn(qd) is not determined by the data (the paper's 1 Hz trajectories put a sample exactly on
  // every velocity reversal; there any estimate of the sign is as good as the record's).
  const Dataset d = test::multisineRecord(10.0, true, false);
  ASSERT_GT(test::multisineRecord(10.0, true, true).qd_radps->cwiseAbs().minCoeff(), 1e-5);
  const ParamVector truth = toParamVector(defaultLeg());
  EXPECT_LT(maxRelError(stackedLs(processRecord(d, test::kLeg, parallel())), truth), 1e-6);
}

// A long log is processed a block at a time (bounded memory): the same rows as the whole record
// at once to rounding, because each block carries parallelBlockMargin samples of context on both
// sides, where the filters' responses to its own edges have died out; and exact data still give
// exact parameters (each block is filtered alike on both sides of tau = Y x).
TEST(ParallelProcessing, BlocksOfALongLogGiveTheWholeRecordsRows) {
  const Dataset d = test::multisineRecord(30.0, true, false);  // angles only: pre-filter and differences too
  SignalOptions whole = parallel(), blocks = parallel();
  whole.block_samples = 1000000;
  blocks.block_samples = 1;  // -> 4 margins (8032 samples at 10 Hz, 1 kHz): four blocks of 30000
  ASSERT_GT(d.size(), 4 * parallelBlockMargin(blocks, 1000.0) + 2 * parallelBlockMargin(blocks, 1000.0));
  const ProcessedRecord a = processRecord(d, test::kLeg, whole), b = processRecord(d, test::kLeg, blocks);
  ASSERT_EQ(a.size(), b.size());
  const double scale = a.hip.cwiseAbs().maxCoeff() + a.knee.cwiseAbs().maxCoeff();
  EXPECT_LT((a.hip - b.hip).cwiseAbs().maxCoeff(), 1e-12 * scale);
  EXPECT_LT((a.knee - b.knee).cwiseAbs().maxCoeff(), 1e-12 * scale);
  EXPECT_LT((a.tau_Nm - b.tau_Nm).cwiseAbs().maxCoeff(), 1e-12 * a.tau_Nm.cwiseAbs().maxCoeff());
  EXPECT_TRUE(a.states.t_s == b.states.t_s);
  EXPECT_LT((a.states.qdd_radps2 - b.states.qdd_radps2).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT(maxRelError(stackedLs(b), toParamVector(defaultLeg())), 1e-6);
}

// The blocks on several threads: each is computed alone and stacked in order, so the rows are
// the same bytes as on one thread (the promise behind identify --threads).
TEST(ParallelProcessing, BlocksOnSeveralThreadsAreTheSameBytesAsOnOne) {
  const Dataset d = test::multisineRecord(30.0, true, false);
  SignalOptions one = parallel();
  one.block_samples = 1;  // four blocks of 30000
  one.threads = 1;
  const ProcessedRecord a = processRecord(d, test::kLeg, one);
  for (int threads : {2, 3, 0}) {
    SignalOptions many = one;
    many.threads = threads;
    const ProcessedRecord b = processRecord(d, test::kLeg, many);
    EXPECT_TRUE(a.hip == b.hip && a.knee == b.knee && a.tau_Nm == b.tau_Nm) << threads << " threads";
    EXPECT_TRUE(a.states.qdd_radps2 == b.states.qdd_radps2 && a.states.t_s == b.states.t_s) << threads << " threads";
  }
  SignalOptions bad = one;
  bad.threads = -1;
  EXPECT_THROW(processRecord(d, test::kLeg, bad), std::invalid_argument);
}

// Recorded velocities without accelerations are used (their derivative gives qdd), not silently
// dropped for the angles' differences: exact data still give exact parameters, and a wrong
// velocity column changes the answer.
TEST(ParallelProcessing, RecordedVelocitiesAloneAreUsed) {
  Dataset d = test::multisineRecord(10.0, true, true);
  d.qdd_radps2.reset();
  const ParamVector truth = toParamVector(defaultLeg());
  EXPECT_LT(maxRelError(stackedLs(processRecord(d, test::kLeg, parallel())), truth), 1e-6);
  Dataset wrong = d;
  *wrong.qd_radps *= 1.1;
  EXPECT_GT(maxRelError(stackedLs(processRecord(wrong, test::kLeg, parallel())), truth), 1e-3);
}

TEST(ParallelProcessing, ThePapersProcessingIsBiasedOnTheSameExactData) {
  // The reason for the parallel processing: the paper's filters the signals, then builds the
  // nonlinear columns, which are then not the filtered columns.
  const ParamVector truth = toParamVector(defaultLeg());
  EXPECT_GT(maxRelError(stackedLs(processRecord(test::multisineRecord(10.0, true, true), test::kLeg, SignalOptions{})), truth), 1e-3);
}

TEST(ParallelProcessing, NoisyTorquesScatterAsTheNoiseCovarianceSays) {
  // 200 seeds of 0.5 N m white torque noise: the sample std of each parameter lies in the
  // chi-square band of its predicted std (z = 3.89, probability 1e-4 per parameter).
  const Dataset d = test::multisineRecord(5.0, true, true);
  const SignalOptions o = parallel();
  const ProcessedRecord r0 = processRecord(d, test::kLeg, o);
  const TorqueNoisePath path = torqueNoisePath(o, 1000.0, d.size());
  const Eigen::VectorXd predicted = stdOf(lsNoiseCovariance({{r0.hip, path, 0.5}, {r0.knee, path, 0.5}}));
  std::mt19937_64 gen(21);
  std::normal_distribution<double> noise(0.0, 0.5);
  const int n = 200;
  Eigen::MatrixXd draws(kNumParams, n);
  for (int k = 0; k < n; ++k) {
    Dataset noisy = d;
    noisy.tau_Nm += Eigen::MatrixX2d::NullaryExpr(d.size(), 2, [&] { return noise(gen); });
    draws.col(k) = stackedLs(processRecord(noisy, test::kLeg, o));
  }
  const double z = 3.89, dof = n - 1.0, v = 2.0 / (9.0 * dof);
  const double lo = std::pow(1.0 - v - z * std::sqrt(v), 1.5), hi = std::pow(1.0 - v + z * std::sqrt(v), 1.5);
  const Eigen::VectorXd mean = draws.rowwise().mean();
  for (int i = 0; i < kNumParams; ++i) {
    const double sd = std::sqrt((draws.row(i).array() - mean[i]).square().sum() / dof);
    EXPECT_GT(sd / predicted[i], lo) << paramName(i);
    EXPECT_LT(sd / predicted[i], hi) << paramName(i);
  }
}

TEST(ParallelProcessing, OptionsAreValidated) {
  SignalOptions o = parallel();
  o.decimation = -1;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = parallel();
  o.decimation = 400;  // 10 s at 1 kHz leaves 24 rows: fine; 1 s leaves 1: refused
  Dataset d = test::multisineRecord(1.0, true, true);
  EXPECT_THROW(processRecord(d, test::kLeg, o), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::ident

namespace exoid::ident {
namespace {

// The multisine record on a pedestal that shakes (fore-aft and vertical at 3.1 and 4.7 Hz, pitch
// at 2.3 Hz), with its IMU columns and torques from the base-motion regressor (itself checked
// against MuJoCo's inverse dynamics in tests/integration).
Dataset shakenRecord() {
  Dataset d = test::multisineRecord(10.0, true, true);
  const LegConstants c{0.45, 9.81};
  const ParamVector x = toParamVector(defaultLeg());
  d.extra_names = {"base_acc_x", "base_acc_z", "base_gyro_y"};
  d.extra.resize(d.size(), 3);
  for (Eigen::Index i = 0; i < d.size(); ++i) {
    const double t = d.t_s[i], w = 2 * M_PI * 2.3;
    const BaseMotion b{0.8 * std::sin(2 * M_PI * 3.1 * t), 9.81 + 0.6 * std::sin(2 * M_PI * 4.7 * t),
                       0.02 * std::sin(w * t), 0.02 * w * std::cos(w * t)};
    d.extra.row(i) << b.f_x_mps2, b.f_z_mps2, b.omega_radps;
    RegressorRow hip, knee;
    regressorRows(c, d.q_rad.row(i).transpose(), d.qd_radps->row(i).transpose(), d.qdd_radps2->row(i).transpose(), b, hip, knee);
    d.tau_Nm.row(i) << hip.dot(x), knee.dot(x);
  }
  return d;
}

TEST(BaseTerms, ExactDataOnAMovingBaseGiveExactParametersWithTheBaseTerms) {
  // The gyro is differentiated (five-point, after the 50 Hz pre-filter): error (w dt)^4 / 30 =
  // 1.5e-9 relative at 2.3 Hz, and the pitch terms are ~1 % of the torque: 1e-6 is ample.
  const Dataset d = shakenRecord();
  const ParamVector truth = toParamVector(defaultLeg());
  SignalOptions o = parallel();
  o.base_terms = BaseTerms::kAuto;
  EXPECT_LT(maxRelError(stackedLs(processRecord(d, test::kLeg, o)), truth), 1e-6);
  // Without them the shaking is unexplained torque, correlated with the motion's columns.
  o.base_terms = BaseTerms::kOff;
  EXPECT_GT(maxRelError(stackedLs(processRecord(d, test::kLeg, o)), truth), 1e-3);
}

TEST(BaseTerms, StillBaseIsTheRegressorAndTheFieldRotatesWithTheLeg) {
  RegressorRow h0, k0, h1, k1;
  const Eigen::Vector2d q(-0.4, 0.9), qd(0.7, -1.1), qdd(3.0, -5.0);
  regressorRows(test::kLeg, q, qd, qdd, h0, k0);
  regressorRows(test::kLeg, q, qd, qdd, BaseMotion::still(test::kLeg.gravity_mps2), h1, k1);
  EXPECT_EQ(h0, h1);
  EXPECT_EQ(k0, k1);
  // A field tilted by beta acts on the still links like gravity on links turned by beta.
  const double beta = 0.3;
  const BaseMotion tilted{-test::kLeg.gravity_mps2 * std::sin(beta), test::kLeg.gravity_mps2 * std::cos(beta), 0.0, 0.0};
  regressorRows(test::kLeg, q, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), tilted, h0, k0);
  regressorRows(test::kLeg, Eigen::Vector2d(q[0] + beta, q[1]), Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), h1, k1);
  EXPECT_LT((h0 - h1).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((k0 - k1).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(BaseTerms, RequiredTermsWithoutImuColumnsAreAnError) {
  SignalOptions o = parallel();
  o.base_terms = BaseTerms::kOn;
  test::expectInvalidArgumentMentioning([&] { processRecord(test::multisineRecord(2.0), test::kLeg, o); }, "base_acc_x");
  o.processing = Processing::kPaper;
  test::expectInvalidArgumentMentioning([&] { o.validate(); }, "needs the parallel processing");
}

}  // namespace
}  // namespace exoid::ident

namespace exoid::ident {
namespace {

// The multisine record with a knee armature: its torque Ia2 qdd2 on the knee equation only.
Dataset armatureRecord(double ia2) {
  Dataset d = test::multisineRecord(10.0, true, true);
  d.tau_Nm.col(1) += ia2 * d.qdd_radps2->col(1);
  return d;
}

TEST(KneeArmature, BothEquationsSeparateItFromJs) {
  // M22 = Js + Ia2 but M12 = Js: the hip equation holds Js alone, so both equations of a record
  // where the hip moves give each. Exact data, parallel processing: exact to rounding.
  const double ia2 = 0.08;
  const ProcessedRecord r = processRecord(armatureRecord(ia2), test::kLeg, parallel());
  const SegmentalProblem with = bothEquations(r, true);
  ASSERT_EQ(with.H.cols(), kNumParams + 1);
  const LsResult ls = solveLeastSquares(with.H, with.y);
  ASSERT_EQ(ls.rank, kNumParams + 1);
  const ParamVector truth = toParamVector(defaultLeg());
  EXPECT_LT(maxRelError(ls.x.head(kNumParams), truth), 1e-8);
  EXPECT_NEAR(ls.x[kKneeArmature], ia2, 1e-8 * ia2);
  // Without the column, Js absorbs it and the rest follows.
  const SegmentalProblem without = bothEquations(r, false);
  EXPECT_GT(maxRelError(solveLeastSquares(without.H, without.y).x, truth), 1e-2);
}

TEST(KneeArmature, WithTheHipFixedOnlyJsPlusIa2IsIdentifiable) {
  // The knee-only record: Js's knee column is qdd1 + qdd2 = qdd2, the armature's too.
  Dataset d = test::multisineRecord(10.0, false, true);
  const ProcessedRecord r = processRecord(d, test::kLeg, parallel());
  Eigen::MatrixXd H(r.size(), 6);
  H << r.knee.middleCols(kShankFirst, kGroupSize), r.knee_armature;
  EXPECT_EQ(solveLeastSquares(H, r.tau_Nm.col(1)).rank, 5);
}

}  // namespace
}  // namespace exoid::ident
