#include "exoid/ident/leg/metrics.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace exoid::ident {
namespace {

TEST(Metrics, TorqueErrorOfAKnownSample) {
  // |e| = 1, 2, 3, 4: mean 2.5, population std sqrt(1.25), rms sqrt(7.5), max 4.
  const Eigen::Vector4d measured(1.0, -2.0, 3.0, 0.0), predicted(0.0, 0.0, 0.0, 4.0);
  const TorqueErrorStats s = torqueError(measured, predicted);
  EXPECT_DOUBLE_EQ(s.mean_abs, 2.5);
  EXPECT_DOUBLE_EQ(s.std_abs, std::sqrt(1.25));
  EXPECT_DOUBLE_EQ(s.rms, std::sqrt(7.5));
  EXPECT_DOUBLE_EQ(s.max_abs, 4.0);
  EXPECT_THROW(torqueError(Eigen::Vector2d(1, 2), Eigen::Vector3d(1, 2, 3)), std::invalid_argument);
}

TEST(Metrics, ParameterErrorOfAKnownVector) {
  const Eigen::Vector3d truth(2.0, -4.0, 4.0), est(3.0, -4.0, 2.0);
  const ParamError e = paramError(est, truth);
  EXPECT_DOUBLE_EQ(e.abs[0], 1.0);
  EXPECT_DOUBLE_EQ(e.rel[0], 0.5);
  EXPECT_DOUBLE_EQ(e.rel[1], 0.0);
  EXPECT_DOUBLE_EQ(e.rel[2], -0.5);
  EXPECT_DOUBLE_EQ(e.norm_rel, std::sqrt(5.0) / 6.0);
  EXPECT_DOUBLE_EQ(e.max_abs_rel, 0.5);
  EXPECT_THROW(paramError(est, Eigen::Vector3d::Zero()), std::invalid_argument);
}

TEST(TorqueSpaceError, ClosedFormForOneParameter) {
  // An error d in hip Coulomb friction only: the knee rows have 0 in that column, so the knee
  // score is 0; the hip score is |d| ||sgn(qd1)|| / ||Y_hip x*|| = |d| sqrt(N) / ||Y_hip x*||
  // (no validation state has qd1 = 0 exactly).
  const LegConstants c{0.45, 9.81};
  const ParamVector truth = toParamVector(defaultLeg());
  ParamVector x = truth;
  x[kFc1] += 0.3;
  const TorqueSpaceError e = torqueSpaceError(x, truth, c);
  const JointSignals s = validationStates();
  const double ref = (jointRegressor(s, Joint::kHip, c) * truth).norm();
  EXPECT_NEAR(e.hip, 0.3 * std::sqrt(static_cast<double>(kValidationStates)) / ref, 1e-12);
  EXPECT_EQ(e.knee, 0.0);
  const TorqueSpaceError zero = torqueSpaceError(truth, truth, c);
  EXPECT_EQ(zero.hip, 0.0);
  EXPECT_EQ(zero.knee, 0.0);
}

TEST(TorqueSpaceError, ValidationStatesAreFixedAndInRange) {
  const JointSignals a = validationStates(), b = validationStates();
  EXPECT_EQ(a.q_rad, b.q_rad);
  EXPECT_EQ(a.qdd_radps2, b.qdd_radps2);
  const double deg = M_PI / 180.0;
  EXPECT_GE(a.q_rad.col(0).minCoeff(), -90 * deg);
  EXPECT_LE(a.q_rad.col(0).maxCoeff(), 30 * deg);
  EXPECT_GE(a.q_rad.col(1).minCoeff(), 0.0);
  EXPECT_LE(a.q_rad.col(1).maxCoeff(), 110 * deg);
  EXPECT_LE(a.qd_radps.cwiseAbs().maxCoeff(), 3.0);
  EXPECT_LE(a.qdd_radps2.cwiseAbs().maxCoeff(), 30.0);
}

}  // namespace
}  // namespace exoid::ident
