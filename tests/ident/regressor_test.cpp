#include "exoid/ident/leg/regressor.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <random>

namespace exoid::ident {
namespace {

// Both sides are O(10) N m sums of O(10) terms in double precision: agreement to 1e-12 relative
// is roundoff; 1e-9 leaves margin for a different summation order and nothing more.
constexpr double kRelTol = 1e-9;

TEST(Regressor, EqualsIndependentDynamicsAtRandomStates) {
  std::mt19937_64 gen(42);
  std::uniform_real_distribution<double> angle(-2.0, 2.0), rate(-6.0, 6.0), acc(-60.0, 60.0);
  std::uniform_real_distribution<double> mass(0.5, 20.0), len(0.1, 0.6), off(-0.2, 0.2), inertia(0.01, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    LegPhysical leg;
    leg.thigh = {mass(gen), len(gen), len(gen), off(gen), inertia(gen)};
    leg.shank = {mass(gen), len(gen), len(gen), off(gen), inertia(gen)};
    leg.fc_hip_Nm = inertia(gen);
    leg.fv_hip_Nms = inertia(gen);
    leg.fc_knee_Nm = inertia(gen);
    leg.fv_knee_Nms = inertia(gen);
    const LegConstants c{leg.thigh.length_m, 9.81};
    const ParamVector x = toParamVector(leg);
    const Eigen::Vector2d q(angle(gen), angle(gen)), qd(rate(gen), rate(gen)), qdd(acc(gen), acc(gen));
    RegressorRow hip, knee;
    regressorRows(c, q, qd, qdd, hip, knee);
    const Eigen::Vector2d expected = test::inverseDynamics(leg, c.gravity_mps2, q, qd, qdd);
    const double scale = std::max(1.0, expected.cwiseAbs().maxCoeff());
    EXPECT_NEAR(hip.dot(x), expected[0], kRelTol * scale) << "trial " << trial;
    EXPECT_NEAR(knee.dot(x), expected[1], kRelTol * scale) << "trial " << trial;
  }
}

TEST(Regressor, HipRowHasNoKneeFrictionAndKneeRowNoThighColumns) {
  RegressorRow hip, knee;
  regressorRows(LegConstants{}, {0.3, 0.5}, {1.0, -2.0}, {3.0, 4.0}, hip, knee);
  EXPECT_EQ(hip[kFc2], 0.0);  // the print has sgn(qd1) here
  EXPECT_EQ(hip[kFv2], 0.0);
  EXPECT_EQ(knee.head<5>().cwiseAbs().sum(), 0.0);
}

TEST(Regressor, StackedRowsAreInterleavedInTime) {
  const LegPhysical leg = defaultLeg();
  const JointSignals s = test::exactRecord(3, leg, 9.81, 0.05);
  const LegConstants c{0.45, 9.81};
  const Eigen::MatrixXd Y = stackedRegressor(s, c);
  const Eigen::VectorXd T = stackedTorque(s);
  ASSERT_EQ(Y.rows(), 2 * s.size());
  const Eigen::MatrixXd Hh = jointRegressor(s, Joint::kHip, c), Hk = jointRegressor(s, Joint::kKnee, c);
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    EXPECT_EQ((Y.row(2 * i) - Hh.row(i)).norm(), 0.0);
    EXPECT_EQ((Y.row(2 * i + 1) - Hk.row(i)).norm(), 0.0);
    EXPECT_EQ(T[2 * i], s.tau_Nm(i, 0));
    EXPECT_EQ(T[2 * i + 1], s.tau_Nm(i, 1));
  }
  const Eigen::MatrixX2d pred = predictTorque(s, toParamVector(leg), c);
  EXPECT_LT((pred - s.tau_Nm).cwiseAbs().maxCoeff(), 1e-9 * s.tau_Nm.cwiseAbs().maxCoeff());
}

TEST(Regressor, RejectsBadConstantsAndSignals) {
  JointSignals s = test::exactRecord(1, defaultLeg(), 9.81, 0.01);
  EXPECT_THROW(jointRegressor(s, Joint::kHip, LegConstants{-1.0, 9.81}), std::invalid_argument);
  s.tau_Nm(3, 1) = std::nan("");
  EXPECT_THROW(stackedRegressor(s, LegConstants{}), std::invalid_argument);
}

TEST(Params, DefaultLegIsPaperSetB) {
  const ParamVector x = toParamVector(defaultLeg());
  ParamVector expected;
  expected << 5.83, 2.60, 3.4545, 1.5, 0.6, 1.28, -0.32, 0.5952, 0.35, 0.25;  // paper.md
  EXPECT_LT((x - expected).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Params, NamesRoundTrip) {
  for (int i = 0; i < kNumParams; ++i) EXPECT_EQ(paramIndex(paramName(i)), i);
  EXPECT_EQ(paramIndex("nope"), -1);
  EXPECT_EQ(paramName(kKneeArmature), "Ia2");  // the optional 11th parameter
  EXPECT_THROW(paramName(11), std::invalid_argument);
  EXPECT_THROW(paramName(-1), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::ident
