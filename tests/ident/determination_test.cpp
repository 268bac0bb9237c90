// What a record's own motion determines, on both legs: a record in which every joint moves
// determines every parameter; one whose hip never moves (locked, or within its encoder's noise)
// leaves exactly the hip's link and joint parameters undetermined: the paper's Mxt, Myt, Jt, fc1,
// fv1 on the APAL leg (its segmental hip stage), the base parameters led by thigh.* and hip.* on
// the 3-joint chain; an IMU's noise on a still base determines nothing either.
#include "exoid/ident/model/determination.hpp"
#include "exoid/ident/signals/preprocess.hpp"
#include "random_chain.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <random>

namespace exoid::ident {
namespace {

struct LegCase {
  std::string name;
  Robot robot;
  Dataset record;            ///< every joint moving, exact
  std::vector<int> hip_own;   ///< the parameters only the hip's motion shows
  std::vector<int> knee_own;  ///< the parameters only the knee's motion shows, the hip's aside
};

LegCase apalLeg() {
  return {"apal", twoLinkLeg(test::kLeg), test::multisineRecord(10.0, true, false), {kMxt, kMyt, kJt, kFc1, kFv1}, {kMxs, kMys, kJs, kFc2, kFv2}};
}

LegCase chainLeg() {
  const ChainModel model = testing::legChain();
  std::mt19937_64 gen(11);
  const Eigen::VectorXd phi = testing::randomPhysicalParameters(gen, model);
  LegCase c{"leg3 chain", chainRobot(model), testing::exactChainDataset(model, phi, 10.0, 5), {}, {}};
  for (int i = 0; i < c.robot.parameters(); ++i) {
    const std::string& n = c.robot.names()[static_cast<std::size_t>(i)];
    if (n.rfind("thigh.", 0) == 0 || n.rfind("hip.", 0) == 0) c.hip_own.push_back(i);
    if (n.rfind("shank.", 0) == 0 || n.rfind("knee.", 0) == 0) c.knee_own.push_back(i);
  }
  return c;
}

SignalOptions parallel() {
  SignalOptions o;
  o.processing = Processing::kParallel;
  return o;
}

std::vector<int> every(const Robot& r) {
  std::vector<int> all;
  for (int i = 0; i < r.parameters(); ++i) all.push_back(i);
  return all;
}

std::vector<int> undetermined(const LegCase& leg, const Dataset& d) {
  return determination(leg.robot, {d}, processRecord(d, leg.robot, parallel()), every(leg.robot)).undetermined;
}

void addNoise(Dataset& d, double sigma_rad, std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> n(0.0, sigma_rad);
  for (Eigen::Index i = 0; i < d.q_rad.size(); ++i) d.q_rad.data()[i] += n(gen);
}

class DeterminationOnEveryLeg : public ::testing::TestWithParam<LegCase (*)()> {};

TEST_P(DeterminationOnEveryLeg, EveryJointMovingDeterminesEveryParameter) {
  const LegCase leg = GetParam()();
  EXPECT_TRUE(undetermined(leg, leg.record).empty()) << leg.name;
  Dataset noisy = leg.record;
  addNoise(noisy, 2e-4, 3);
  EXPECT_TRUE(undetermined(leg, noisy).empty()) << leg.name;
  const std::vector<SignalMotion> joints = recordMotion(noisy).joints;
  for (const SignalMotion& m : joints) {
    EXPECT_TRUE(m.moved()) << leg.name << " " << m.name;
    EXPECT_NEAR(m.noise, 2e-4, 2e-5) << leg.name << " " << m.name;  // the encoder's noise, estimated
  }
}

TEST_P(DeterminationOnEveryLeg, AHeldHipLeavesExactlyTheHipsOwnParameters) {
  const LegCase leg = GetParam()();
  ASSERT_FALSE(leg.hip_own.empty());
  for (const double give_rad : {0.0, 1e-5}) {
    Dataset held = leg.record;
    for (Eigen::Index i = 0; i < held.size(); ++i) held.q_rad(i, 0) = -0.4 + give_rad * std::sin(7.0 * held.t_s[i]);
    EXPECT_EQ(undetermined(leg, held), leg.hip_own) << leg.name << ", give " << give_rad;
    // Within an encoder's noise, the same.
    addNoise(held, 2e-4, 4);
    EXPECT_EQ(undetermined(leg, held), leg.hip_own) << leg.name << ", noisy";
    const Determination d = determination(leg.robot, {held}, processRecord(held, leg.robot, parallel()), every(leg.robot));
    EXPECT_NE(d.describe(leg.robot).find(leg.robot.jointNames().front() + " held in every record"), std::string::npos) << d.describe(leg.robot);
  }
  // The hip's parameters left to another stage (not among the unknowns): the rest is determined.
  Dataset held = leg.record;
  held.q_rad.col(0).setConstant(-0.4);
  std::vector<int> rest;
  for (int i : every(leg.robot)) {
    if (std::find(leg.hip_own.begin(), leg.hip_own.end(), i) == leg.hip_own.end()) rest.push_back(i);
  }
  EXPECT_TRUE(determination(leg.robot, {held}, processRecord(held, leg.robot, parallel()), rest).undetermined.empty()) << leg.name;
}

// The segmental strategy's stages, each judged on its own motion over its own equations and what it
// fits, as the fit runs: a hip-held record fitting the lower joints' parameters, then a record
// where every joint moves fitting the rest, determine everything; the held record in both stages
// leaves the hip's own parameters; a first (hip-held) stage whose knee was held too leaves the
// knee's own, however well the last stage's hip equation sees them (they are fitted in the first
// stage alone: judged over every stage together, only the knee's friction would be named).
TEST_P(DeterminationOnEveryLeg, EachStageIsJudgedOnItsOwnMotion) {
  const LegCase leg = GetParam()();
  const Robot& robot = leg.robot;
  std::vector<int> lower, rest;
  for (int i : every(robot)) {
    bool in_lower = false;
    for (std::size_t j = 1; j < robot.joint_columns.size(); ++j) {
      const std::vector<int>& c = robot.joint_columns[j];
      in_lower = in_lower || std::find(c.begin(), c.end(), i) != c.end();
    }
    (in_lower ? lower : rest).push_back(i);
  }
  EXPECT_EQ(rest, leg.hip_own) << leg.name;
  std::vector<Eigen::Index> lower_equations(static_cast<std::size_t>(robot.dof() - 1));
  for (std::size_t j = 0; j < lower_equations.size(); ++j) lower_equations[j] = static_cast<Eigen::Index>(j + 1);
  Dataset hip_held = leg.record, knee_held = leg.record;
  hip_held.q_rad.col(0).setConstant(-0.4);
  knee_held.q_rad.col(0).setConstant(-0.4);  // the segmental knee record, its knee held too
  knee_held.q_rad.col(1).setConstant(0.3);
  const std::vector<Dataset> hip_held_records = {hip_held}, knee_held_records = {knee_held}, moving_records = {leg.record};
  const RecordRows hip_held_rows = processRecord(hip_held, robot, parallel()), knee_held_rows = processRecord(knee_held, robot, parallel()),
                   moving_rows = processRecord(leg.record, robot, parallel());
  const auto stages = [&](const std::vector<Dataset>& first, const RecordRows& first_rows, const std::vector<Dataset>& last,
                          const RecordRows& last_rows) {
    return determination(robot, {{&first, &first_rows, lower_equations, parameterDirections(robot, lower)},
                                 {&last, &last_rows, {}, parameterDirections(robot, rest)}});
  };
  const Determination good = stages(hip_held_records, hip_held_rows, moving_records, moving_rows);
  EXPECT_TRUE(good.undetermined.empty()) << leg.name << ": " << good.describe(robot);
  EXPECT_EQ(good.records.size(), 2u);
  EXPECT_EQ(stages(hip_held_records, hip_held_rows, hip_held_records, hip_held_rows).undetermined, leg.hip_own) << leg.name;
  const Determination knee_open = stages(knee_held_records, knee_held_rows, moving_records, moving_rows);
  EXPECT_EQ(knee_open.undetermined, leg.knee_own) << leg.name << ": " << knee_open.describe(robot);
  EXPECT_THROW(determination(robot, {{&moving_records, &moving_rows, {}, Eigen::MatrixXd::Identity(2, 2)}}), std::invalid_argument);
}

TEST_P(DeterminationOnEveryLeg, AnImusNoiseOnAStillBaseDeterminesNothing) {
  const LegCase leg = GetParam()();
  Dataset held = leg.record;
  held.q_rad.col(0).setConstant(-0.4);
  // The IMU of a still base: gravity and noise (0.015 m/s^2, 0.001 rad/s, as the simulated rig's).
  std::mt19937_64 gen(5);
  std::normal_distribution<double> acc(0.0, 0.015), gyro(0.0, 0.001);
  held.extra_names = {"base_acc_x", "base_acc_z", "base_gyro_y"};
  held.extra.resize(held.size(), 3);
  for (Eigen::Index i = 0; i < held.size(); ++i) held.extra.row(i) << acc(gen), 9.81 + acc(gen), gyro(gen);
  ASSERT_TRUE(hasBaseColumns(held));
  const Determination d = determination(leg.robot, {held}, processRecord(held, leg.robot, parallel()), every(leg.robot));
  EXPECT_FALSE(d.records.front().baseMoved());
  EXPECT_EQ(d.undetermined, leg.hip_own) << leg.name;
  // A base that shakes (1 m/s^2 fore-aft at 3 Hz) moved.
  for (Eigen::Index i = 0; i < held.size(); ++i) held.extra(i, 0) += std::sin(2 * M_PI * 3.0 * held.t_s[i]);
  EXPECT_TRUE(recordMotion(held).baseMoved());
}

INSTANTIATE_TEST_SUITE_P(Legs, DeterminationOnEveryLeg, ::testing::Values(&apalLeg, &chainLeg),
                         [](const ::testing::TestParamInfo<LegCase (*)()>& leg) { return leg.index == 0 ? "Apal" : "Leg3Chain"; });

TEST(Determination, RecordsAndRowsMustAgree) {
  const LegCase leg = apalLeg();
  const RecordRows rows = processRecord(leg.record, leg.robot, parallel());
  EXPECT_THROW(determination(leg.robot, {leg.record, leg.record}, rows, every(leg.robot)), std::invalid_argument);
  EXPECT_THROW(recordMotion(Dataset{}), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::ident
