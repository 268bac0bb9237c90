#include "exoid/ident/estimators/least_squares.hpp"

#include "exoid/ident/estimators/segmental.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

namespace exoid::ident {
namespace {


// Noise-free data from an independent dynamics: LS must return X to roundoff amplified by the
// condition number (~1e3 for the stacked record): 1e-16 * 1e3 * margin << 1e-8.
TEST(LeastSquares, RecoversTruthFromExactTwoJointRecord) {
  const LegPhysical leg = defaultLeg();
  const ParamVector truth = toParamVector(leg);
  const JointSignals s = test::exactRecord(3, leg, test::kLeg.gravity_mps2);
  const LsResult r = solveLeastSquares(stackedRegressor(s, test::kLeg), stackedTorque(s));
  ASSERT_EQ(r.summary.status, Status::kConverged) << r.summary.message;
  EXPECT_EQ(r.rank, 10);
  for (int i = 0; i < kNumParams; ++i) EXPECT_NEAR(r.x[i], truth[i], 1e-8 * std::abs(truth[i])) << paramName(i);
  EXPECT_GT(r.condition_number, 1.0);
}

TEST(LeastSquares, ReportsRankDeficiencyNamingColumns) {
  // Trajectory 1 fixes the hip: the hip equation's thigh columns are constant or zero.
  const JointSignals s = test::exactRecord(1, defaultLeg(), test::kLeg.gravity_mps2);
  const Eigen::MatrixXd H = jointRegressor(s, Joint::kHip, test::kLeg).leftCols(5);
  const LsResult r = solveLeastSquares(H, s.tau_Nm.col(0));
  EXPECT_EQ(r.summary.status, Status::kRankDeficient);
  EXPECT_LT(r.rank, 5);
  EXPECT_EQ(r.unidentifiable.size(), static_cast<std::size_t>(5 - r.rank));
  EXPECT_NE(r.summary.message.find("cannot be separated"), std::string::npos);
  EXPECT_TRUE(r.x.allFinite());
}

TEST(LeastSquares, IllConditionedFullRankProblemIsNotUsable) {
  // Two columns differing by 1e-7 relative: full rank (above the 1e-8 rank tolerance) but the
  // scaled condition number is ~1e7 > max_condition = 1e5.
  Eigen::MatrixXd H = Eigen::MatrixXd::Random(200, 3);
  H.col(2) = H.col(0) + 1e-7 * Eigen::VectorXd::Random(200);
  const LsResult r = solveLeastSquares(H, Eigen::VectorXd::Random(200));
  EXPECT_EQ(r.rank, 3);
  EXPECT_GT(r.condition_number, 1e5);
  EXPECT_EQ(r.summary.status, Status::kIllConditioned);
  EXPECT_FALSE(usable(r.summary.status));
  EXPECT_NE(r.summary.message.find("ill-conditioned"), std::string::npos) << r.summary.message;
  EXPECT_NE(r.summary.message.find("max_condition"), std::string::npos) << r.summary.message;
  // The bound is the option: raised above the condition, the same fit is usable.
  LsOptions lenient;
  lenient.max_condition = 10.0 * r.condition_number;
  EXPECT_EQ(solveLeastSquares(H, Eigen::VectorXd::Random(200), lenient).summary.status, Status::kConverged);
  const LsResult ok = solveLeastSquares(Eigen::MatrixXd::Random(200, 3), Eigen::VectorXd::Random(200));
  EXPECT_EQ(ok.summary.status, Status::kConverged);
}

TEST(LeastSquares, ScaledConditionNumberIsTheRatioOfSingularValuesOfUnitColumns) {
  // Orthogonal columns of any lengths: condition 1 once scaled. Two unit columns at angle a:
  // singular values sqrt(1 +- cos a), so the condition is sqrt((1 + cos a) / (1 - cos a)).
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(4, 2);
  H(0, 0) = 3.0;
  H(1, 1) = 1e-6;
  EXPECT_NEAR(scaledConditionNumber(H), 1.0, 1e-12);
  const double a = 0.1;
  H.setZero();
  H(0, 0) = 5.0;
  H(0, 1) = 2.0 * std::cos(a);
  H(1, 1) = 2.0 * std::sin(a);
  EXPECT_NEAR(scaledConditionNumber(H), std::sqrt((1 + std::cos(a)) / (1 - std::cos(a))), 1e-9);
  EXPECT_THROW(scaledConditionNumber(Eigen::MatrixXd::Ones(1, 2)), std::invalid_argument);
}

TEST(LeastSquares, DuplicateColumnIsUnidentifiable) {
  Eigen::MatrixXd H = Eigen::MatrixXd::Random(50, 3);
  H.col(2) = 2.0 * H.col(0);
  const LsResult r = solveLeastSquares(H, Eigen::VectorXd::Random(50));
  EXPECT_EQ(r.summary.status, Status::kRankDeficient);
  EXPECT_EQ(r.rank, 2);
}

TEST(LeastSquares, RejectsBadInput) {
  EXPECT_THROW(solveLeastSquares(Eigen::MatrixXd::Ones(3, 5), Eigen::VectorXd::Ones(3)), std::invalid_argument);
  EXPECT_THROW(solveLeastSquares(Eigen::MatrixXd::Ones(10, 2), Eigen::VectorXd::Ones(9)), std::invalid_argument);
  Eigen::MatrixXd H = Eigen::MatrixXd::Ones(10, 2);
  H(0, 0) = std::nan("");
  EXPECT_THROW(solveLeastSquares(H, Eigen::VectorXd::Ones(10)), std::invalid_argument);
  LsOptions o;
  o.rank_tolerance = 2.0;
  try {
    solveLeastSquares(Eigen::MatrixXd::Ones(10, 2), Eigen::VectorXd::Ones(10), o);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'rank_tolerance'"), std::string::npos);
  }
}

}  // namespace
}  // namespace exoid::ident
