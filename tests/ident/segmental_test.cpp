// The segmental strategy down any robot: exact records give the exact parameters (the APAL leg's
// X from its hand-written rows, any chain's base parameters), each stage fits only what the joints
// it moves determine (the APAL leg's knee stage: the knee's five, from the knee equation; its last
// stage the hip equation with the knee part subtracted, the paper's Eq. 9), a lock that makes a
// link's inertia and its joint's armature act alike leaves their split to a later stage, and stage
// lists that cannot work are refused with the reason.
#include "exoid/ident/estimators/segmental.hpp"

#include "exoid/ident/estimators/segmental_errors.hpp"

#include "random_chain.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

namespace exoid::ident {
namespace {

using testing::apalChain;
using testing::randomChain;
using testing::randomPhysicalParameters;

// An exact record: joints first..tip follow a two-frequency motion with analytic derivatives,
// the joints above are locked (constant angle, zero rates); torque = W phi, no noise.
SegmentalStage exactStage(const Robot& robot, const Eigen::VectorXd& theta, Eigen::Index first, std::uint64_t seed) {
  const ChainModel& m = robot.chain;
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> amp(0.3, 0.9), freq(0.3, 1.7), phase(0.0, 6.28), lock(-1.0, 1.0);
  const Eigen::Index n = 600, dof = m.dof();
  JointSignals s;
  s.t_s = Eigen::VectorXd::LinSpaced(n, 0.0, 0.01 * static_cast<double>(n - 1));
  s.q_rad.resize(n, dof);
  s.qd_radps.resize(n, dof);
  s.qdd_radps2.resize(n, dof);
  s.tau_Nm = Eigen::MatrixXd::Zero(n, dof);
  for (Eigen::Index j = 0; j < dof; ++j) {
    if (j < first) {
      s.q_rad.col(j).setConstant(lock(gen));
      s.qd_radps.col(j).setZero();
      s.qdd_radps2.col(j).setZero();
      continue;
    }
    const double a1 = amp(gen), w1 = 2 * M_PI * freq(gen), p1 = phase(gen), a2 = 0.4 * amp(gen), w2 = 2 * M_PI * freq(gen) * 2.3, p2 = phase(gen);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double t = s.t_s[i];
      s.q_rad(i, j) = a1 * std::sin(w1 * t + p1) + a2 * std::sin(w2 * t + p2);
      s.qd_radps(i, j) = a1 * w1 * std::cos(w1 * t + p1) + a2 * w2 * std::cos(w2 * t + p2);
      s.qdd_radps2(i, j) = -a1 * w1 * w1 * std::sin(w1 * t + p1) - a2 * w2 * w2 * std::sin(w2 * t + p2);
    }
  }
  SegmentalStage st;
  st.first_joint = first;
  st.record = recordRows(robot, s);
  st.record.y = st.record.W * theta;
  return st;
}

double relativeError(const Eigen::VectorXd& x, const Eigen::VectorXd& truth) {
  return (x - truth).cwiseAbs().maxCoeff() / truth.cwiseAbs().maxCoeff();
}

TEST(Segmental, ApalLegKneeStageFitsTheKneesFiveThenTheHipsFive) {
  const Robot robot = chainRobot(apalChain(0.45));
  std::mt19937_64 gen(3);
  const Eigen::VectorXd phi = randomPhysicalParameters(gen, robot.chain);
  const Eigen::VectorXd beta = robot.basis.combination * phi;
  const std::vector<SegmentalStage> stages = {exactStage(robot, beta, 1, 11), exactStage(robot, beta, 0, 12)};
  const SegmentalResult r = identifySegmental(robot, stages, Method::kLs, MethodOptions{});
  ASSERT_EQ(r.stages.size(), 2u);
  // Stage 1 fits the knee's equation: five combinations, each a whole base parameter of the shank
  // or the knee (the paper's Mxs, Mys, Js, fc2, fv2), so a search box there is per parameter.
  const StageProblem& knee = r.stages[0].problem;
  EXPECT_EQ(knee.directions.cols(), 5);
  EXPECT_EQ(knee.parameters.size(), 5u);
  EXPECT_EQ(knee.rows.size(), 600u);
  for (const std::string& name : knee.names) {
    EXPECT_EQ(name.find("thigh"), std::string::npos) << name;
    EXPECT_EQ(name.find("hip"), std::string::npos) << name;
    EXPECT_EQ(name.find(" + "), std::string::npos) << name << ": not a whole base parameter";
  }
  // Stage 2 the thigh's five from the hip's equation alone: the knee's holds none of them.
  EXPECT_EQ(r.stages[1].problem.directions.cols(), 5);
  EXPECT_EQ(r.stages[1].problem.rows.size(), 600u);
  // Exact data: the exact base parameters (least squares over exact rows: rounding only).
  EXPECT_LT(relativeError(r.theta, beta), 1e-10);
}

// The APAL leg in the paper's X (its hand-written rows): the stages' problems are the paper's, the
// knee's columns Mxs .. fv2 of the knee equation, then Mxt .. fv1 of the hip equation with
// H_hip(6:10) X(6:10) subtracted (Eq. 9), and exact records give the truth.
TEST(Segmental, TheApalLegsStagesAreThePapersAndRecoverTheTruthFromExactRecords) {
  const LegPhysical leg = defaultLeg();
  const ParamVector truth = toParamVector(leg);
  const Robot robot = twoLinkLeg(test::kLeg);
  const RecordRows knee = recordRows(robot, test::exactRecord(1, leg, test::kLeg.gravity_mps2));
  const RecordRows both = recordRows(robot, test::exactRecord(3, leg, test::kLeg.gravity_mps2));
  const SegmentalPlan plan(robot, {1, 0});
  const StageProblem k = plan.problem(0, knee, {});
  EXPECT_EQ(k.parameters, (std::vector<int>{kMxs, kMys, kJs, kFc2, kFv2}));
  EXPECT_TRUE(k.H == knee.jointW(1).middleCols(kShankFirst, kGroupSize));
  EXPECT_TRUE(k.y == knee.jointY(1));
  const Eigen::VectorXd x_knee = truth.segment<kGroupSize>(kShankFirst);
  const StageProblem h = plan.problem(1, both, {x_knee});
  EXPECT_EQ(h.parameters, (std::vector<int>{kMxt, kMyt, kJt, kFc1, kFv1}));
  EXPECT_TRUE(h.H == both.jointW(0).middleCols(kThighFirst, kGroupSize));
  const Eigen::VectorXd knee_part = both.jointW(0).middleCols(kShankFirst, kGroupSize) * x_knee;
  EXPECT_TRUE(h.y == both.jointY(0) - knee_part);
  const SegmentalResult r = identifySegmental(robot, {{1, knee}, {0, both}}, Method::kLs, MethodOptions{});
  for (const StageResult& st : r.stages) ASSERT_TRUE(usable(st.estimate.summary.status)) << st.estimate.summary.message;
  for (int i = 0; i < kNumParams; ++i) EXPECT_NEAR(r.theta[i], truth[i], 1e-8 * std::abs(truth[i])) << paramName(i);
}

TEST(Segmental, RandomSpatialChainsDownFourStagesAreExact) {
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    std::mt19937_64 gen(seed);
    const ChainModel m = randomChain(gen, 4);  // armature on joints 1 and 3
    const Eigen::VectorXd phi = randomPhysicalParameters(gen, m);
    const Robot robot = chainRobot(m);
    const Eigen::VectorXd beta = robot.basis.combination * phi;
    std::vector<SegmentalStage> stages;
    for (Eigen::Index first = 3; first >= 0; --first) stages.push_back(exactStage(robot, beta, first, 100 * seed + static_cast<std::uint64_t>(first)));
    const SegmentalResult r = identifySegmental(robot, stages, Method::kLs, MethodOptions{});
    Eigen::Index total = 0;
    for (const StageResult& s : r.stages) total += s.problem.directions.cols();
    EXPECT_EQ(total, robot.parameters()) << "seed " << seed;
    EXPECT_LT(relativeError(r.theta, beta), 1e-8) << "seed " << seed;
    // LAD composes the same way (its exact optimum on exact rows is the truth too).
    const SegmentalResult l = identifySegmental(robot, stages, Method::kLad, MethodOptions{});
    EXPECT_LT(relativeError(l.theta, beta), 1e-6) << "seed " << seed;
  }
}

TEST(Segmental, ALockThatJoinsInertiaAndArmatureLeavesTheSplitToTheNextStage) {
  // Planar: the APAL leg with knee armature, in its chain's base parameters and in X + Ia2. Hip
  // locked, the knee's acceleration is the shank's: stage 1 fits shank inertia + armature as one
  // combination (Js + Ia2); the two-joint stage separates them.
  ChainModel m = apalChain(0.45);
  m.joints[1].armature = true;
  std::mt19937_64 gen(5);
  const Eigen::VectorXd phi = randomPhysicalParameters(gen, m);
  for (const Robot& robot : {chainRobot(m), twoLinkLeg(LegConstants{0.45, 9.81}, true)}) {
    ASSERT_EQ(robot.parameters(), 11);
    const Eigen::VectorXd theta = robot.basis.combination * phi;
    const SegmentalResult r =
        identifySegmental(robot, {exactStage(robot, theta, 1, 21), exactStage(robot, theta, 0, 22)}, Method::kLs, MethodOptions{});
    EXPECT_EQ(r.stages[0].problem.directions.cols(), 5);
    bool joined = false;
    for (const std::string& name : r.stages[0].problem.names) {
      joined = joined || ((name.find("knee.Ia") != std::string::npos || name.find("Ia2") != std::string::npos) && name.find(" + ") != std::string::npos);
    }
    EXPECT_TRUE(joined) << "stage 1 should fit the shank's inertia and the knee's armature as one sum";
    EXPECT_EQ(r.stages[1].problem.directions.cols(), 6);
    EXPECT_LT(relativeError(r.theta, theta), 1e-10);
  }
}

TEST(Segmental, RefusesWhatCannotWork) {
  const Robot robot = chainRobot(apalChain(0.45));
  std::mt19937_64 gen(7);
  const Eigen::VectorXd beta = robot.basis.combination * randomPhysicalParameters(gen, robot.chain);
  const SegmentalStage knee = exactStage(robot, beta, 1, 1), both = exactStage(robot, beta, 0, 2);
  const auto message = [&](const std::vector<SegmentalStage>& stages) {
    try {
      identifySegmental(robot, stages, Method::kLs, MethodOptions{});
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no refusal");
  };
  EXPECT_NE(message({}).find("no stages"), std::string::npos);
  EXPECT_NE(message({both, knee}).find("distal joints first"), std::string::npos);
  EXPECT_NE(message({knee}).find("leave 5 combination(s) unidentified"), std::string::npos) << message({knee});
  EXPECT_NE(message({knee, knee}).find("identifies no combination"), std::string::npos);
}


// The reported errors of a segmental LS fit against Monte Carlo: the APAL leg's knee and hip
// stages, white torque noise of 5 % of each record's RMS torque, 400 seeds. The knee values' errors
// carry into the hip's (the hip stage subtracts the knee part), which the hip stage's own
// residuals cannot show.
TEST(SegmentalErrors, FollowTheScatterOverSeedsWithWhatTheEarlierStagesCarry) {
  const Robot robot = chainRobot(apalChain(0.45));
  std::mt19937_64 gen(3);
  const Eigen::VectorXd beta = robot.basis.combination * randomPhysicalParameters(gen, robot.chain);
  const std::vector<SegmentalStage> exact = {exactStage(robot, beta, 1, 11), exactStage(robot, beta, 0, 12)};
  constexpr int kSeeds = 400;
  const Eigen::Index p = robot.parameters();
  Eigen::MatrixXd errors(kSeeds, p), reported(kSeeds, p), newey_west(kSeeds, p), own(kSeeds, p);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (int k = 0; k < kSeeds; ++k) {
    std::vector<SegmentalStage> noisy = exact;
    for (std::size_t s = 0; s < noisy.size(); ++s) {
      const double sigma = 0.05 * std::sqrt(exact[s].record.y.squaredNorm() / static_cast<double>(exact[s].record.y.size()));
      for (Eigen::Index i = 0; i < noisy[s].record.y.size(); ++i) noisy[s].record.y[i] += sigma * n01(gen);
    }
    const SegmentalResult r = identifySegmental(robot, noisy, Method::kLs, MethodOptions{});
    const ReportedErrors e = segmentalReportedErrors(robot, noisy, r);
    errors.row(k) = (r.theta - beta).transpose();
    reported.row(k) = e.reported.transpose();
    newey_west.row(k) = e.newey_west.transpose();
    // The last (hip) stage's own Newey-West alone, without what the knee stage carries.
    const SegmentalPlan plan(robot, {1, 0});
    const StageProblem hip = plan.problem(1, noisy[1].record, {r.stages[0].estimate.x});
    const Eigen::MatrixXd c = residualCovariance(hip.H, hip.y - hip.H * r.stages[1].estimate.x, interleavedChannels(hip.H.rows(), 1), -1, 1);
    own.row(k) = e.newey_west.transpose();
    for (std::size_t i = 0; i < hip.parameters.size(); ++i) own(k, hip.parameters[i]) = std::sqrt(c(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)));
  }
  // The scatter's sd from 400 seeds is within 4 of its standard errors (1 / sqrt(2 x 399): 3.5 %)
  // of the mean reported Newey-West error; coverage of -+ 1.96 reported errors no more than 4
  // binomial sd (1.1 %) below 95 %.
  int carried_matters = 0;
  for (Eigen::Index i = 0; i < p; ++i) {
    const double sd = std::sqrt((errors.col(i).array() - errors.col(i).mean()).square().sum() / (kSeeds - 1));
    const double nw = newey_west.col(i).mean();
    EXPECT_NEAR(sd / nw, 1.0, 4.0 / std::sqrt(2.0 * (kSeeds - 1))) << robot.names()[static_cast<std::size_t>(i)];
    const int held = static_cast<int>(((errors.col(i).array().abs()) <= 1.96 * reported.col(i).array()).count());
    EXPECT_GE(held, static_cast<int>(std::floor(kSeeds * (0.95 - 4.0 * std::sqrt(0.95 * 0.05 / kSeeds)))))
        << robot.names()[static_cast<std::size_t>(i)];
    if (own.col(i).mean() < (1.0 - 4.0 / std::sqrt(2.0 * (kSeeds - 1))) * sd) ++carried_matters;
    std::printf("[ info ] %s: scatter / Newey-West %.3f, scatter / the last stage's own %.3f, coverage %.3f\n",
                robot.names()[static_cast<std::size_t>(i)].c_str(), sd / nw, sd / own.col(i).mean(), held / double(kSeeds));
  }
  EXPECT_GE(carried_matters, 1) << "the test has no power: no hip parameter's own error misses the knee stage's share";
}

// With one stage (every joint moving) the segmental errors are one fit's: reportedErrors on the
// same rows.
TEST(SegmentalErrors, OneStageIsOneFitsReportedErrors) {
  const Robot robot = chainRobot(apalChain(0.45));
  std::mt19937_64 gen(4);
  const Eigen::VectorXd beta = robot.basis.combination * randomPhysicalParameters(gen, robot.chain);
  std::vector<SegmentalStage> stages = {exactStage(robot, beta, 0, 21)};
  std::normal_distribution<double> n01(0.0, 0.05);
  for (Eigen::Index i = 0; i < stages[0].record.y.size(); ++i) stages[0].record.y[i] += n01(gen);
  const SegmentalResult r = identifySegmental(robot, stages, Method::kLs, MethodOptions{});
  const ReportedErrors seg = segmentalReportedErrors(robot, stages, r);
  const RecordRows& rows = stages[0].record;
  const ReportedErrors one = reportedErrors(rows.W, rows.y, r.theta, interleavedChannels(rows.W.rows(), 1), static_cast<int>(rows.dof),
                                            recordBlocks(rows.record_rows, rows.W.rows(), static_cast<int>(rows.dof)),
                                            wholeRecords(rows.record_rows, rows.W.rows()));
  for (Eigen::Index i = 0; i < robot.parameters(); ++i) {
    EXPECT_NEAR(seg.reported[i], one.reported[i], 1e-9 * one.reported[i]) << robot.names()[static_cast<std::size_t>(i)];
    EXPECT_NEAR(seg.newey_west[i], one.newey_west[i], 1e-9 * one.newey_west[i]);
  }
}

}  // namespace
}  // namespace exoid::ident
