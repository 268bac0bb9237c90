// The processing of every leg's records (signals/processing.hpp): parallel filtering and decimation
// (Processing::kParallel) give the exact parameters on exact data whatever the filter, with
// recorded derivatives or with angles alone, a long log a block at a time as whole, on any number
// of threads, on a still or a shaking base; noisy data scatter as the noise covariance of the same
// processing says; the paper's processing does not have the first property (the review measured
// up to 38 % on exact data). Each is checked on the APAL leg (its hand-written rows, the fast path)
// and on a hip-knee-ankle chain (the RNEA regressor in base parameters); the fast path's rows equal
// the chain's for the same leg.
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/estimators/noise_covariance.hpp"
#include "exoid/ident/signals/processing.hpp"
#include "exoid/ident/model/determination.hpp"
#include "random_chain.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <random>

namespace exoid::ident {
namespace {

SignalOptions parallel() {
  SignalOptions o;
  o.processing = Processing::kParallel;
  return o;
}

Eigen::VectorXd stackedLs(const RecordRows& r) { return solveLeastSquares(r.W, r.y).x; }

double maxRelError(const Eigen::VectorXd& x, const Eigen::VectorXd& truth) {
  return ((x - truth).cwiseQuotient(truth.cwiseAbs())).cwiseAbs().maxCoeff();
}

// A leg and exact records of it: `record(seconds, recorded derivatives, base motion)`, and its truth.
struct LegCase {
  std::string name;
  Robot robot;
  std::function<Dataset(double, bool)> record;
  Eigen::VectorXd truth;
  /// Exactness from estimated derivatives is checked to 1e-6 of max(|truth|, floor): relative on the
  /// APAL leg's X; with a floor of 1 on a chain's base parameters (as band_iv_test's), some of which
  /// are small (ankle.fc 0.057) against the columns' scale, where the derivatives' error, the same
  /// in absolute terms, is no longer 1e-6 of the parameter.
  double tolerance_floor = 0.0;
};

// max |x - truth| / max(|truth|, leg's floor).
double maxScaledError(const LegCase& leg, const Eigen::VectorXd& x) {
  return (x - leg.truth).cwiseQuotient(leg.truth.cwiseAbs().cwiseMax(leg.tolerance_floor)).cwiseAbs().maxCoeff();
}

LegCase apalLeg() {
  return {"apal", twoLinkLeg(test::kLeg), [](double s, bool derivatives) { return test::multisineRecord(s, true, derivatives); },
          toParamVector(defaultLeg())};
}

ChainModel armedLeg() {
  ChainModel model = testing::legChain();
  model.joints[2].armature = true;
  return model;
}

Eigen::VectorXd armedLegPhi() {
  std::mt19937_64 gen(11);
  return testing::randomPhysicalParameters(gen, armedLeg());
}

LegCase chainLeg() {
  Robot robot = chainRobot(armedLeg());
  const Eigen::VectorXd truth = robot.basis.combination * armedLegPhi();
  return {"leg3 chain", robot, [](double s, bool derivatives) { return testing::exactChainDataset(armedLeg(), armedLegPhi(), s, 5, derivatives); },
          truth, 1.0};
}

class ProcessingOnEveryLeg : public ::testing::TestWithParam<LegCase (*)()> {};

TEST_P(ProcessingOnEveryLeg, ExactDataGiveExactParametersWithRecordedDerivatives) {
  // filter(tau) = filter(Y) x exactly: only rounding, amplified by the condition number (~1e3).
  const LegCase leg = GetParam()();
  const RecordRows r = processRecord(leg.record(10.0, true), leg.robot, parallel());
  EXPECT_EQ(r.samples(), (10000 - 2 * 300 + 19) / 20);  // trimmed 0.3 s each end, every 20th row
  EXPECT_EQ(r.W.rows(), r.samples() * leg.robot.dof());
  EXPECT_LT(maxRelError(stackedLs(r), leg.truth), 1e-8) << leg.name;
}

TEST_P(ProcessingOnEveryLeg, ExactDataGiveExactParametersFromAnglesAlone) {
  // Angles only: five-point derivatives of the pre-filtered angles, error (w dt)^4 / 30 <= 3e-9
  // relative at the 1.9 Hz harmonic (the chain's fastest: 3.9 Hz, 5e-8), pre-filter gain loss
  // (1.9 / 50)^8 = 4e-12: far below the 1e-6 promised. Precondition: no sample within the
  // derivative error of zero velocity, where sgn(qd) is not determined by the data (the paper's
  // 1 Hz trajectories put a sample exactly on every velocity reversal; there any estimate of the
  // sign is as good as the record's).
  const LegCase leg = GetParam()();
  ASSERT_GT(leg.record(10.0, true).qd_radps->cwiseAbs().minCoeff(), 1e-5);
  EXPECT_LT(maxScaledError(leg, stackedLs(processRecord(leg.record(10.0, false), leg.robot, parallel()))), 1e-6) << leg.name;
}

// A long log is processed a block at a time (bounded memory): the same rows as the whole record
// at once to rounding, because each block carries parallelBlockMargin samples of context on both
// sides, where the filters' responses to its own edges have died out; and exact data still give
// exact parameters (each block is filtered alike on both sides of tau = Y x).
TEST_P(ProcessingOnEveryLeg, BlocksOfALongLogGiveTheWholeRecordsRows) {
  const LegCase leg = GetParam()();
  const Dataset d = leg.record(30.0, false);  // angles only: pre-filter and differences too
  SignalOptions whole = parallel(), blocks = parallel();
  whole.block_samples = 1000000;
  blocks.block_samples = 1;  // -> 4 margins (4196 samples at 10 Hz, 1 kHz): eight blocks of 30000
  ASSERT_GT(d.size(), 4 * parallelBlockMargin(blocks, 1000.0) + 2 * parallelBlockMargin(blocks, 1000.0));
  const RecordRows a = processRecord(d, leg.robot, whole), b = processRecord(d, leg.robot, blocks);
  ASSERT_EQ(a.W.rows(), b.W.rows());
  EXPECT_LT((a.W - b.W).cwiseAbs().maxCoeff(), 1e-12 * a.W.cwiseAbs().maxCoeff()) << leg.name;
  EXPECT_LT((a.y - b.y).cwiseAbs().maxCoeff(), 1e-12 * a.y.cwiseAbs().maxCoeff()) << leg.name;
  EXPECT_TRUE(a.states.t_s == b.states.t_s);
  EXPECT_LT((a.states.qdd_radps2 - b.states.qdd_radps2).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT(maxScaledError(leg, stackedLs(b)), 1e-6) << leg.name;
  // Still one record (its residual's correlation, its jackknife blocks, what its motion determines).
  EXPECT_EQ(b.record_rows, a.record_rows) << leg.name;
  std::vector<int> every(static_cast<std::size_t>(leg.robot.parameters()));
  for (int i = 0; i < leg.robot.parameters(); ++i) every[static_cast<std::size_t>(i)] = i;
  EXPECT_TRUE(determination(leg.robot, {d}, b, every).undetermined.empty()) << leg.name;
}

// The blocks on several threads: each is computed alone and stacked in order, so the rows are
// the same bytes as on one thread (the promise behind identify --threads).
TEST_P(ProcessingOnEveryLeg, BlocksOnSeveralThreadsAreTheSameBytesAsOnOne) {
  const LegCase leg = GetParam()();
  const Dataset d = leg.record(30.0, false);
  SignalOptions one = parallel();
  one.block_samples = 1;  // eight blocks of 30000
  one.threads = 1;
  const RecordRows a = processRecord(d, leg.robot, one);
  for (int threads : {2, 3, 0}) {
    SignalOptions many = one;
    many.threads = threads;
    const RecordRows b = processRecord(d, leg.robot, many);
    EXPECT_TRUE(a.W == b.W && a.y == b.y) << leg.name << ", " << threads << " threads";
    EXPECT_TRUE(a.states.qdd_radps2 == b.states.qdd_radps2 && a.states.t_s == b.states.t_s) << threads << " threads";
  }
  SignalOptions bad = one;
  bad.threads = -1;
  EXPECT_THROW(processRecord(d, leg.robot, bad), std::invalid_argument);
}

// An exact record of `leg` on a base moving as shake(t) says, with its IMU columns (specific force,
// pitch rate) and the torques of the base-motion regressor (itself checked against MuJoCo's inverse
// dynamics in tests/integration).
Dataset recordOnBase(const LegCase& leg, const std::function<ChainBaseMotion(double)>& shake) {
  Dataset d = leg.record(10.0, true);
  d.extra_names = {"base_acc_x", "base_acc_z", "base_gyro_y"};
  d.extra.resize(d.size(), 3);
  RobotWorkspace work;
  Eigen::MatrixXd Y(leg.robot.dof(), leg.robot.parameters());
  for (Eigen::Index i = 0; i < d.size(); ++i) {
    const ChainBaseMotion b = shake(d.t_s[i]);
    d.extra.row(i) << b.specific_force_mps2.x(), b.specific_force_mps2.z(), b.omega_radps.y();
    robotRowsInto(leg.robot, d.q_rad.row(i).transpose(), d.qd_radps->row(i).transpose(), d.qdd_radps2->row(i).transpose(), b, work, Y);
    d.tau_Nm.row(i) = (Y * leg.truth).transpose();
  }
  return d;
}

// Fore-aft and vertical at 3.1 and 4.7 Hz, pitch at 2.3 Hz.
ChainBaseMotion shaking(double t) {
  const double w = 2 * M_PI * 2.3;
  ChainBaseMotion b;
  b.specific_force_mps2 = Eigen::Vector3d(0.8 * std::sin(2 * M_PI * 3.1 * t), 0.0, 9.81 + 0.6 * std::sin(2 * M_PI * 4.7 * t));
  b.omega_radps = Eigen::Vector3d(0.0, 0.02 * std::sin(w * t), 0.0);
  b.alpha_radps2 = Eigen::Vector3d(0.0, 0.02 * w * std::cos(w * t), 0.0);
  return b;
}

// A shaking base: exact with the base-motion terms, and wrong without them.
TEST_P(ProcessingOnEveryLeg, ExactDataOnAShakingBaseGiveExactParametersWithTheBaseTerms) {
  const LegCase leg = GetParam()();
  const Dataset d = recordOnBase(leg, shaking);
  // The gyro is differentiated (five-point, after the 50 Hz pre-filter): error (w dt)^4 / 30 =
  // 1.5e-9 relative at 2.3 Hz, and the pitch terms are ~1 % of the torque: 1e-6 is ample.
  SignalOptions o = parallel();
  o.base_terms = BaseTerms::kAuto;
  EXPECT_LT(maxScaledError(leg, stackedLs(processRecord(d, leg.robot, o))), 1e-6) << leg.name;
  // Without them the shaking is unexplained torque, correlated with the motion's columns.
  o.base_terms = BaseTerms::kOff;
  EXPECT_GT(maxRelError(stackedLs(processRecord(d, leg.robot, o)), leg.truth), 1e-3) << leg.name;
}

// --base-terms judged keeps the terms where the base moves and drops them where it stands still.
// Shaking, exact: with the terms every held-out block is predicted exactly (residual ~ the
// derivatives' error), without them the shaking is left unexplained, so they are kept and the
// parameters are exact. Still, with a noisy IMU (0.3 m/s^2, 0.05 rad/s): without the terms the
// record is exact, with them the IMU's noise enters every row and no parameter absorbs it, so
// they are dropped and the parameters are exact again. kAuto is never judged.
TEST_P(ProcessingOnEveryLeg, JudgedBaseTermsAreKeptOnAShakingBaseAndDroppedOnAStillOne) {
  const LegCase leg = GetParam()();
  SignalOptions o = parallel();
  o.base_terms = BaseTerms::kJudged;
  std::optional<BaseTermsChoice> choice;
  const Dataset shaken = recordOnBase(leg, shaking);
  SignalOptions used = resolveSignalOptions(shaken, leg.robot, o, {}, nullptr, &choice);
  ASSERT_TRUE(choice.has_value()) << leg.name;
  EXPECT_TRUE(choice->use) << choice->describe();
  EXPECT_EQ(used.base_terms, BaseTerms::kAuto);  // kept: as the default, whenever a record has the columns
  EXPECT_LT(choice->held_out_rms_with_Nm, 1e-3 * choice->held_out_rms_without_Nm) << choice->describe();
  EXPECT_LT(maxScaledError(leg, stackedLs(processRecord(shaken, leg.robot, o))), 1e-6) << leg.name;

  Dataset still = recordOnBase(leg, [&](double) { return ChainBaseMotion::still(leg.robot.chain); });
  std::mt19937_64 gen(11);
  std::normal_distribution<double> unit(0.0, 1.0);
  for (Eigen::Index i = 0; i < still.size(); ++i) still.extra.row(i) += Eigen::RowVector3d(0.3 * unit(gen), 0.3 * unit(gen), 0.05 * unit(gen));
  used = resolveSignalOptions(still, leg.robot, o, {}, nullptr, &choice);
  ASSERT_TRUE(choice.has_value());
  EXPECT_FALSE(choice->use) << choice->describe();
  EXPECT_EQ(used.base_terms, BaseTerms::kOff);
  EXPECT_NE(choice->describe().find("dropped"), std::string::npos);
  EXPECT_LT(maxScaledError(leg, stackedLs(processRecord(still, leg.robot, o))), 1e-6) << leg.name;

  o.base_terms = BaseTerms::kAuto;
  used = resolveSignalOptions(still, leg.robot, o, {}, nullptr, &choice);
  EXPECT_FALSE(choice.has_value());
  EXPECT_EQ(used.base_terms, BaseTerms::kAuto);
  EXPECT_THROW(chooseBaseTerms(test::multisineRecord(2.0), leg.robot, parallel()), std::invalid_argument);  // no IMU columns
  // Judged without IMU columns: nothing to judge, the default's kAuto (not judged again later).
  o.base_terms = BaseTerms::kJudged;
  used = resolveSignalOptions(leg.record(2.0, true), leg.robot, o, {}, nullptr, &choice);
  EXPECT_FALSE(choice.has_value());
  EXPECT_EQ(used.base_terms, BaseTerms::kAuto);
}

// Records fitted together share one choice: their held-out squared errors pooled over their
// equations (the RMS of all of them), a record too short to judge not counted.
TEST(BaseTermsChoice, RecordsFittedTogetherPoolTheirHeldOutErrors) {
  BaseTermsChoice kept, dropped, unjudged;
  kept.folds = dropped.folds = 5;
  kept.equations = 300;
  kept.held_out_rms_with_Nm = 1.0;
  kept.held_out_rms_without_Nm = 2.0;
  dropped.equations = 100;
  dropped.held_out_rms_with_Nm = 5.0;
  dropped.held_out_rms_without_Nm = 3.0;
  dropped.use = false;
  unjudged.equations = 0;
  unjudged.held_out_rms_with_Nm = 100.0;
  const std::optional<BaseTermsChoice> p = pooledBaseTerms({kept, std::nullopt, dropped, unjudged});
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->equations, 400);
  EXPECT_DOUBLE_EQ(p->held_out_rms_with_Nm, std::sqrt((300 * 1.0 + 100 * 25.0) / 400));    // 2.65
  EXPECT_DOUBLE_EQ(p->held_out_rms_without_Nm, std::sqrt((300 * 4.0 + 100 * 9.0) / 400));  // 2.29
  EXPECT_FALSE(p->use);
  EXPECT_FALSE(pooledBaseTerms({unjudged, std::nullopt}).has_value());
}

INSTANTIATE_TEST_SUITE_P(Legs, ProcessingOnEveryLeg, ::testing::Values(&apalLeg, &chainLeg),
                         [](const ::testing::TestParamInfo<LegCase (*)()>& leg) { return leg.index == 0 ? "Apal" : "Leg3Chain"; });

// The 2-link leg's hand-written rows (the fast path) and the RNEA regressor of its chain in base
// parameters are the same model: for any standard parameters phi, the torques Y_X (G phi) and
// Y_base (C phi) agree at every row of a processed record, paper's processing and parallel,
// still base and shaking (the paper's X is a basis of the chain's base parameters).
TEST(ProcessingFastPath, TheTwoLinkRowsAreTheChainsInAnotherBasis) {
  const Robot x_leg = twoLinkLeg(test::kLeg, true), chain = chainRobot(twoLinkChain(test::kLeg, true));
  std::mt19937_64 gen(5);
  const Eigen::VectorXd phi = testing::randomPhysicalParameters(gen, x_leg.chain);
  const Eigen::VectorXd x = x_leg.basis.combination * phi, beta = chain.basis.combination * phi;
  const Dataset d = test::multisineRecord(10.0, true, false);
  for (const Processing p : {Processing::kPaper, Processing::kParallel}) {
    SignalOptions o = parallel();
    o.processing = p;
    const RecordRows a = processRecord(d, x_leg, o), b = processRecord(d, chain, o);
    ASSERT_EQ(a.W.rows(), b.W.rows());
    const Eigen::VectorXd ta = a.W * x, tb = b.W * beta;
    EXPECT_LT((ta - tb).cwiseAbs().maxCoeff(), 1e-12 * tb.cwiseAbs().maxCoeff()) << toString(p);
    EXPECT_TRUE(a.y == b.y) << toString(p);
  }
}

// Recorded velocities without accelerations are used (their derivative gives qdd), not silently
// dropped for the angles' differences: exact data still give exact parameters, and a wrong
// velocity column changes the answer.
TEST(ParallelProcessing, RecordedVelocitiesAloneAreUsed) {
  Dataset d = test::multisineRecord(10.0, true, true);
  d.qdd_radps2.reset();
  const ParamVector truth = toParamVector(defaultLeg());
  EXPECT_LT(maxRelError(stackedLs(processRecord(d, twoLinkLeg(test::kLeg), parallel())), truth), 1e-6);
  Dataset wrong = d;
  *wrong.qd_radps *= 1.1;
  EXPECT_GT(maxRelError(stackedLs(processRecord(wrong, twoLinkLeg(test::kLeg), parallel())), truth), 1e-3);
}

TEST(ParallelProcessing, ThePapersProcessingIsBiasedOnTheSameExactData) {
  // The reason for the parallel processing: the paper's filters the signals, then builds the
  // nonlinear columns, which are then not the filtered columns.
  const ParamVector truth = toParamVector(defaultLeg());
  EXPECT_GT(maxRelError(stackedLs(processRecord(test::multisineRecord(10.0, true, true), twoLinkLeg(test::kLeg), SignalOptions{})), truth), 1e-3);
}

TEST(ParallelProcessing, NoisyTorquesScatterAsTheNoiseCovarianceSays) {
  // 200 seeds of 0.5 N m white torque noise: the sample std of each parameter lies in the
  // chi-square band of its predicted std (z = 3.89, probability 1e-4 per parameter).
  const Dataset d = test::multisineRecord(5.0, true, true);
  const SignalOptions o = parallel();
  const RecordRows r0 = processRecord(d, twoLinkLeg(test::kLeg), o);
  const TorqueNoisePath path = torqueNoisePath(o, 1000.0, d.size());
  const Eigen::VectorXd predicted = stdOf(lsNoiseCovariance({{r0.jointW(0), path, 0.5}, {r0.jointW(1), path, 0.5}}));
  std::mt19937_64 gen(21);
  std::normal_distribution<double> noise(0.0, 0.5);
  const int n = 200;
  Eigen::MatrixXd draws(kNumParams, n);
  for (int k = 0; k < n; ++k) {
    Dataset noisy = d;
    noisy.tau_Nm += Eigen::MatrixX2d::NullaryExpr(d.size(), 2, [&] { return noise(gen); });
    draws.col(k) = stackedLs(processRecord(noisy, twoLinkLeg(test::kLeg), o));
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
  EXPECT_THROW(processRecord(d, twoLinkLeg(test::kLeg), o), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::ident

namespace exoid::ident {
namespace {

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
  test::expectInvalidArgumentMentioning([&] { processRecord(test::multisineRecord(2.0), twoLinkLeg(test::kLeg), o); }, "base_acc_x");
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
  const RecordRows with = processRecord(armatureRecord(ia2), twoLinkLeg(test::kLeg, true), parallel());
  ASSERT_EQ(with.W.cols(), kNumParams + 1);
  const LsResult ls = solveLeastSquares(with.W, with.y);
  ASSERT_EQ(ls.rank, kNumParams + 1);
  const ParamVector truth = toParamVector(defaultLeg());
  EXPECT_LT(maxRelError(ls.x.head(kNumParams), truth), 1e-8);
  EXPECT_NEAR(ls.x[kKneeArmature], ia2, 1e-8 * ia2);
  // Without the column, Js absorbs it and the rest follows.
  const RecordRows without = processRecord(armatureRecord(ia2), twoLinkLeg(test::kLeg), parallel());
  EXPECT_GT(maxRelError(solveLeastSquares(without.W, without.y).x, truth), 1e-2);
}

TEST(KneeArmature, WithTheHipFixedOnlyJsPlusIa2IsIdentifiable) {
  // The knee-only record: Js's knee column is qdd1 + qdd2 = qdd2, the armature's too.
  const RecordRows r = processRecord(test::multisineRecord(10.0, false, true), twoLinkLeg(test::kLeg, true), parallel());
  const Eigen::MatrixXd knee = r.jointW(1);
  Eigen::MatrixXd H(knee.rows(), 6);
  H << knee.middleCols(kShankFirst, kGroupSize), knee.col(kKneeArmature);
  EXPECT_EQ(solveLeastSquares(H, r.jointY(1)).rank, 5);
}

}  // namespace
}  // namespace exoid::ident
