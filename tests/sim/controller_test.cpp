#include "exoid/sim/controller.hpp"

#include <gtest/gtest.h>

namespace exoid::sim {
namespace {

TEST(PidControllerTest, ProportionalIntegralDerivativeTerms) {
  PidGains g;
  g.kp_Nm_per_rad = {100.0, 10.0};
  g.ki_Nm_per_rad_s = {1000.0, 0.0};
  g.kd_Nms_per_rad = {2.0, 0.0};
  g.derivative_cutoff_Hz = 0.0;  // plain backward difference
  const double dt = 1e-3;
  PidController pid(g, dt);
  pid.reset(Eigen::Vector2d::Zero(), {true, true});
  JointReference ref;
  ref.q = {0.01, 0.02};
  ref.qd = {0.5, 0.0};
  const Eigen::Vector2d u = pid.update(ref, Eigen::Vector2d::Zero());
  // hip: kp e + ki e dt (+ kd de/dt, taken as 0 on the first sample: the controller starts at rest)
  EXPECT_DOUBLE_EQ(u[0], 100 * 0.01 + 1000 * 0.01 * dt);
  EXPECT_DOUBLE_EQ(u[1], 10 * 0.02);
  // measured motion of 1e-3 rad in one step: the error falls by 1e-3 rad, de/dt = -1 rad/s
  const Eigen::Vector2d u2 = pid.update(ref, Eigen::Vector2d(1e-3, 0.0));
  EXPECT_NEAR(u2[0], 100 * 0.009 + 1000 * (0.01 + 0.009) * dt + 2 * (-1.0), 1e-12);
}

TEST(PidControllerTest, DisabledJointOutputsZeroAndIntegralIsPreloaded) {
  PidController pid(PidGains{}, 1e-3);
  pid.reset(Eigen::Vector2d(0.1, 0.2), {false, true}, Eigen::Vector2d(5.0, 7.0));
  JointReference ref;
  ref.q = {0.3, 0.2};
  const Eigen::Vector2d u = pid.update(ref, Eigen::Vector2d(0.1, 0.2));
  EXPECT_EQ(u[0], 0.0);
  EXPECT_DOUBLE_EQ(u[1], 7.0);  // zero error: only the preloaded integral
}

TEST(PidControllerTest, IntegralIsClamped) {
  PidGains g;
  g.integral_limit_Nm = 3.0;
  PidController pid(g, 1e-3);
  pid.reset(Eigen::Vector2d::Zero(), {true, true});
  JointReference ref;
  ref.q = {1.0, 1.0};
  for (int i = 0; i < 1000; ++i) pid.update(ref, Eigen::Vector2d::Zero());
  g.kp_Nm_per_rad.setZero();
  g.kd_Nms_per_rad.setZero();
  PidController only_i(g, 1e-3);
  only_i.reset(Eigen::Vector2d::Zero(), {true, true});
  Eigen::Vector2d u;
  for (int i = 0; i < 1000; ++i) u = only_i.update(ref, Eigen::Vector2d::Zero());
  EXPECT_DOUBLE_EQ(u[0], 3.0);
}

TEST(PidControllerTest, ValidationNamesTheField) {
  PidGains g;
  g.kd_Nms_per_rad[1] = -1;
  try {
    g.validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("gains.kd_Nms_per_rad[knee]"), std::string::npos) << e.what();
  }
  g = {};
  g.integral_limit_Nm = 0;
  EXPECT_THROW(g.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::sim
