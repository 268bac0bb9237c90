// Excitation design on every leg (the APAL leg in its X, a chain in its base parameters): the
// Fourier trajectory's rest-at-the-ends rule, the limits' bookkeeping, determinism; on the APAL
// leg the Cramer-Rao floor no trajectory can beat, and designs that beat the paper's trajectories
// on the criterion they optimise.
#include "exoid/ident/design/excitation.hpp"
#include "exoid/core/random.hpp"
#include "random_chain.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>

#include <algorithm>

#include <cmath>

namespace exoid::ident {
namespace {

const Robot& leg() {
  static const Robot r = twoLinkLeg(test::kLeg);
  return r;
}

// The paper's trajectory 3 (hip -30 - 30 sin, knee 75 - 30 sin, 1 Hz) as a Fourier trajectory.
core::FourierSeries paperTrajectory3() {
  const double d = M_PI / 180.0;
  core::FourierSeries t = core::FourierSeries::still(2, 1, 1.0);
  t.offset_rad << -30 * d, 75 * d;
  t.b_rad << -30 * d, -30 * d;
  return t;
}

TEST(Excitation, LimitsAreReportedByNameAndSize) {
  ExcitationLimits lim = ExcitationLimits::twoLinkLeg();
  lim.qd_max_radps << 3.0, 1.0;  // trajectory 3 reaches 30 deg * 2 pi = 3.29 rad/s on both joints
  const ExcitationScore s = scoreExcitation(leg(), paperTrajectory3(), toParamVector(defaultLeg()), lim);
  EXPECT_NEAR(s.qd_max_radps[1], 30.0 * M_PI / 180.0 * 2 * M_PI, 1e-3);
  EXPECT_EQ(s.worst_violation_name, "qd[knee]");
  EXPECT_NEAR(s.worst_violation, s.qd_max_radps[1] / 1.0 - 1.0, 1e-12);
}

// The floor's column bounds hold at every state inside the limits (checked on random states with
// the regressor itself), and Coulomb friction's floor is sigma / sqrt(rows) exactly.
TEST(Excitation, CrbFloorBoundsEveryColumnInsideTheLimits) {
  ExcitationLimits lim = ExcitationLimits::twoLinkLeg();
  lim.q_min_rad << -1.3, 0.2;
  lim.q_max_rad << 0.1, 1.9;
  lim.qd_max_radps << 3.0, 4.0;
  lim.qdd_max_radps2 << 20.0, 25.0;
  // sigma = 1, rows = 1: floor_i = 1 / sqrt(b_hip_i^2 + b_knee_i^2).
  const Eigen::VectorXd floor = crbFloor(lim, test::kLeg, false, 0.0, 1.0, 1.0);
  ASSERT_EQ(floor.size(), kNumParams);
  EXPECT_DOUBLE_EQ(floor[kFc1], 1.0);
  EXPECT_DOUBLE_EQ(floor[kFc2], 1.0);
  EXPECT_DOUBLE_EQ(floor[kFv1], 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(floor[kJt], 1.0 / std::hypot(20.0, 0.0));
  EXPECT_DOUBLE_EQ(floor[kJs], 1.0 / std::hypot(25.0, 45.0));
  core::Rng rng(7);
  ParamVector reached = ParamVector::Zero();
  for (int i = 0; i < 200000; ++i) {
    Eigen::Vector2d q, qd, qdd;
    for (int j = 0; j < 2; ++j) {
      q[j] = rng.uniform(lim.q_min_rad[j], lim.q_max_rad[j]);
      qd[j] = rng.uniform(-lim.qd_max_radps[j], lim.qd_max_radps[j]);
      qdd[j] = rng.uniform(-lim.qdd_max_radps2[j], lim.qdd_max_radps2[j]);
    }
    RegressorRow hip, knee;
    regressorRows(test::kLeg, q, qd, qdd, hip, knee);
    for (int p = 0; p < kNumParams; ++p) reached[p] = std::max(reached[p], std::hypot(hip[p], knee[p]) * floor[p]);
  }
  // <= 1: a bound; the friction and inertia columns come close to it (random states do not hit
  // every corner at once, so the coupled gravity-inertia bounds are looser).
  EXPECT_LE(reached.maxCoeff(), 1.0);
  EXPECT_GT(reached[kFc1], 0.999);
  EXPECT_GT(reached[kFv2], 0.99);
  EXPECT_GT(reached[kJs], 0.9);
}

TEST(Excitation, DesignBeatsThePapersTrajectoryAndRespectsItsLimits) {
  const ParamVector nominal = toParamVector(defaultLeg());
  const ExcitationLimits lim = ExcitationLimits::twoLinkLeg();
  ExcitationOptions o;  // defaults: criterion crb, N = 5, f0 = 0.2 Hz, 8 restarts
  const ExcitationDesign d = designExcitation(o, leg(), nominal, lim);
  const ExcitationScore paper = scoreExcitation(leg(), paperTrajectory3(), nominal, lim);
  std::printf("[ info ] condition number: design %.3g (paper's trajectory 3: %.3g), %ld evaluations, %.2f s\n",
              d.score.condition_number, paper.condition_number, d.evaluations, d.wall_time_s);
  EXPECT_EQ(d.score.worst_violation, 0.0) << d.score.worst_violation_name;
  EXPECT_LE(d.score.condition_number, 25.0);  // issue 10's target
  EXPECT_LT(d.score.condition_number, paper.condition_number / 10.0);
  // The criterion it minimised (per sample: the paper's 1 s period and the design's 5 s period
  // are each scored on 1000 samples, so compare per-row information: std scales as 1/sqrt(rows)).
  EXPECT_LT(d.score.sum_log_std, paper.sum_log_std);
  // Nor the floor: no trajectory inside the limits beats it (1000 rows of unit noise per equation).
  const Eigen::MatrixXd H = excitationRegressor(leg(), d.trajectory, 1000);
  const Eigen::MatrixXd cov = (H.transpose() * H).inverse();
  const Eigen::VectorXd floor = crbFloor(lim, test::kLeg, false, 0.0, 1000.0, 1.0);
  for (int p = 0; p < kNumParams; ++p) EXPECT_GE(std::sqrt(cov(p, p)), floor[p]) << paramName(p);
  // At rest at the period's ends.
  Eigen::Vector2d q, qd, qdd;
  d.trajectory.at(0.0, q, qd, qdd);
  EXPECT_LT(qd.cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT(qdd.cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Excitation, ConditionNumberCriterionMeetsItsTargetToo) {
  ExcitationOptions o;
  o.criterion = ExcitationCriterion::kConditionNumber;
  o.restarts = 3;
  const ExcitationDesign d = designExcitation(o, leg(), toParamVector(defaultLeg()), ExcitationLimits::twoLinkLeg());
  EXPECT_EQ(d.score.worst_violation, 0.0) << d.score.worst_violation_name;
  EXPECT_LE(d.score.condition_number, 25.0);
  EXPECT_EQ(parseExcitationCriterion("cond"), ExcitationCriterion::kConditionNumber);
  EXPECT_EQ(parseExcitationCriterion(toString(ExcitationCriterion::kCrb)), ExcitationCriterion::kCrb);
  EXPECT_THROW(parseExcitationCriterion("d-opt"), std::invalid_argument);
}

TEST(Excitation, KneeOnlyDesignKeepsTheHipAtItsLock) {
  ExcitationOptions o;
  o.locked_joints = 1;
  o.locked_at_rad = Eigen::VectorXd::Constant(1, -10.0 * M_PI / 180.0);  // the paper's
  o.restarts = 3;
  const ExcitationDesign d = designExcitation(o, leg(), toParamVector(defaultLeg()), ExcitationLimits::twoLinkLeg());
  EXPECT_EQ(d.score.worst_violation, 0.0) << d.score.worst_violation_name;
  EXPECT_EQ(d.trajectory.a_rad.col(0).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(d.trajectory.offset_rad[0], o.locked_at_rad[0]);
  EXPECT_EQ(d.trajectory.locked_joints, 1);
  // The knee equation's rows over the parameters it touches: the shank's and the knee's five.
  const Eigen::MatrixXd H = excitationRegressor(leg(), d.trajectory, 100);
  EXPECT_EQ(H.rows(), 100);
  EXPECT_EQ(excitationParameters(leg(), 1), (std::vector<int>{kShankFirst, kShankFirst + 1, kShankFirst + 2, kShankFirst + 3, kShankFirst + 4}));
  EXPECT_EQ(H.cols(), kGroupSize);
  EXPECT_EQ(crbFloor(ExcitationLimits::twoLinkLeg(), test::kLeg, true, o.locked_at_rad[0], 1.0, 1.0).size(), kGroupSize);
  std::printf("[ info ] knee-only design: condition number %.3g\n", d.score.condition_number);
}

// A stage's record (the hip held) of a leg whose knee has an armature: in the knee and ankle
// equations the knee armature's column is its link inertia's, so the design leaves it out and is
// for what such a record identifies. Checked on states the selection never saw: every column left
// out lies in the span of those kept, which have full rank.
TEST(Excitation, AHeldJointLeavesOutWhatItsRecordCannotSeparate) {
  ChainModel m = testing::legChain();
  m.joints[1].armature = m.joints[2].armature = true;
  const Robot robot = chainRobot(m);
  const Eigen::VectorXd held = Eigen::VectorXd::Constant(1, 0.1);
  const std::vector<int> kept = excitationParameters(robot, 1, held);
  std::vector<std::string> left_out;
  for (std::size_t j = 1; j < robot.joint_columns.size(); ++j) {
    for (int c : robot.joint_columns[j]) {
      const std::string& name = robot.names()[static_cast<std::size_t>(c)];
      if (std::count(kept.begin(), kept.end(), c) == 0 && std::count(left_out.begin(), left_out.end(), name) == 0) left_out.push_back(name);
    }
  }
  EXPECT_EQ(left_out, std::vector<std::string>{"knee.Ia"});
  // The knee and ankle rows at 200 states drawn here, the hip at its lock.
  core::Rng rng(7);
  Eigen::MatrixXd rows(3, robot.parameters()), H(400, robot.parameters());
  RobotWorkspace work;
  for (int k = 0; k < 200; ++k) {
    Eigen::Vector3d q(held[0], rng.uniform(-2, 2), rng.uniform(-2, 2)), qd(0, rng.uniform(-2, 2), rng.uniform(-2, 2)),
        qdd(0, rng.uniform(-5, 5), rng.uniform(-5, 5));
    robotRowsInto(robot, q, qd, qdd, ChainBaseMotion::still(m), work, rows);
    H.middleRows(2 * k, 2) = rows.bottomRows(2);
  }
  Eigen::MatrixXd K(H.rows(), static_cast<Eigen::Index>(kept.size()));
  for (std::size_t c = 0; c < kept.size(); ++c) K.col(static_cast<Eigen::Index>(c)) = H.col(kept[c]).normalized();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(K);
  // Unit columns over 200 spread states: a dependent set gives ~1e-15, these are separable by a
  // wide margin (a value of order 0.1); 1e-3 tells the two apart.
  EXPECT_GT(svd.singularValues().minCoeff(), 1e-3);
  const int knee_ia = static_cast<int>(std::find(robot.names().begin(), robot.names().end(), "knee.Ia") - robot.names().begin());
  const Eigen::VectorXd col = H.col(knee_ia);
  const Eigen::VectorXd residual = col - K * K.colPivHouseholderQr().solve(col);
  EXPECT_LE(residual.norm(), 1e-12 * col.norm() * static_cast<double>(H.rows()));  // in their span, to rounding
  // The design for that record is well conditioned.
  ExcitationOptions o;
  o.locked_joints = 1;
  o.locked_at_rad = held;
  o.restarts = 1;
  o.max_evaluations = 400;
  ExcitationLimits lim;
  lim.q_min_rad = Eigen::Vector3d(-1.5, -0.1, -0.6);
  lim.q_max_rad = Eigen::Vector3d(0.5, 2.0, 0.6);
  lim.qd_max_radps = Eigen::Vector3d::Constant(3.0);
  lim.qdd_max_radps2 = Eigen::Vector3d::Constant(30.0);
  lim.tau_max_Nm = Eigen::Vector3d::Constant(1e3);
  Eigen::VectorXd phi = Eigen::VectorXd::Zero(m.standardParameterCount());
  for (int j = 0; j < 3; ++j) {
    phi.segment<10>(m.layout()[static_cast<std::size_t>(j)].link) =
        linkParameters(4.0, {0.0, 0.0, -0.2}, Eigen::Vector3d(0.06, 0.06, 0.01).asDiagonal());
  }
  const ExcitationDesign d = designExcitation(o, robot, robot.basis.combination * phi, lim);
  // With the armature's column left in, the design's rows are singular (condition ~1e15).
  EXPECT_LT(d.score.condition_number, 100.0);
}

// Every leg: the APAL leg in its X and the APAL chain in its base parameters (a chain from a
// model file would be the same code). A design starts and ends at rest, stays inside every limit
// (checked on 1000 samples), is the same for the same seed and another for another, and scores as
// the score function says; a motion out of range is a violation that names the joint.
struct LegDesignCase {
  const char* name;
  Robot robot;
  Eigen::VectorXd theta;
};

LegDesignCase apalInX() { return {"APAL leg (X)", twoLinkLeg(test::kLeg), toParamVector(defaultLeg())}; }

LegDesignCase apalChainInBaseParameters() {
  const Robot r = chainRobot(testing::apalChain(0.45));
  Eigen::VectorXd phi(24);
  phi.segment<10>(0) = linkParameters(9.0, {0.0, 0.0, -0.2}, Eigen::Vector3d(0.15, 0.15, 0.03).asDiagonal());
  phi.segment<2>(10) << 1.0, 0.5;
  phi.segment<10>(12) = linkParameters(4.0, {0.0, 0.0, -0.2}, Eigen::Vector3d(0.06, 0.06, 0.01).asDiagonal());
  phi.segment<2>(22) << 0.7, 0.3;
  return {"APAL chain (base parameters)", r, r.basis.combination * phi};
}

class ExcitationOnEveryLeg : public ::testing::TestWithParam<LegDesignCase (*)()> {};

TEST_P(ExcitationOnEveryLeg, FeasibleAtRestAtTheEndsAndDeterministic) {
  const LegDesignCase c = GetParam()();
  ExcitationLimits lim = ExcitationLimits::twoLinkLeg();
  lim.q_min_rad[0] = -1.2;
  lim.q_max_rad[0] = 0.4;
  ExcitationOptions o;
  o.restarts = 2;
  o.max_evaluations = 400;
  const ExcitationDesign a = designExcitation(o, c.robot, c.theta, lim);
  const ExcitationDesign b = designExcitation(o, c.robot, c.theta, lim);
  EXPECT_EQ(a.trajectory.a_rad, b.trajectory.a_rad) << c.name;
  EXPECT_EQ(a.trajectory.b_rad, b.trajectory.b_rad) << c.name;
  EXPECT_EQ(a.trajectory.offset_rad, b.trajectory.offset_rad) << c.name;
  o.seed = 2;
  EXPECT_NE(designExcitation(o, c.robot, c.theta, lim).trajectory.b_rad, a.trajectory.b_rad) << c.name;
  EXPECT_EQ(a.score.worst_violation, 0.0) << c.name << " " << a.score.worst_violation_name;
  Eigen::VectorXd q, qd, qdd;
  a.trajectory.at(0.0, q, qd, qdd);
  EXPECT_LE(qd.cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LE(qdd.cwiseAbs().maxCoeff(), 1e-10);
  a.trajectory.at(1.0 / a.trajectory.f0_hz, q, qd, qdd);
  EXPECT_LE(qd.cwiseAbs().maxCoeff(), 1e-9);
  const ExcitationScore s = scoreExcitation(c.robot, a.trajectory, c.theta, lim, 1000);
  EXPECT_EQ(s.condition_number, a.score.condition_number);
  EXPECT_TRUE(std::isfinite(s.condition_number));
  core::FourierSeries wide = a.trajectory;
  wide.offset_rad[1] = 2.5;
  EXPECT_EQ(scoreExcitation(c.robot, wide, c.theta, lim, 200).worst_violation_name, "q_max[knee]") << c.name;
  o.locked_joints = 2;
  o.locked_at_rad = Eigen::Vector2d::Zero();
  EXPECT_THROW(designExcitation(o, c.robot, c.theta, lim), std::invalid_argument);
}

INSTANTIATE_TEST_SUITE_P(Legs, ExcitationOnEveryLeg, ::testing::Values(&apalInX, &apalChainInBaseParameters),
                         [](const ::testing::TestParamInfo<LegDesignCase (*)()>& i) { return i.index == 0 ? "ApalX" : "ApalChain"; });

}  // namespace
}  // namespace exoid::ident
