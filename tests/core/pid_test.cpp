// The one PID of the rigs and of ident's model of them: its terms, the preloaded and clamped
// integral, a disabled joint, both derivative sources on any number of joints, and validation
// naming the joint.
#include "exoid/core/pid.hpp"

#include <gtest/gtest.h>

namespace exoid::core {
namespace {

// Gains of two joints (the APAL rig's magnitudes).
PidGains twoJointGains() {
  PidGains g;
  g.kp_Nm_per_rad = Eigen::Vector2d(2200.0, 380.0);
  g.ki_Nm_per_rad_s = Eigen::Vector2d(6900.0, 1200.0);
  g.kd_Nms_per_rad = Eigen::Vector2d(176.0, 30.0);
  return g;
}

// u = 0 + the feedback, as the APAL rig adds its feedforward after.
Eigen::Vector2d feedback(PidController& pid, const Eigen::Vector2d& q_ref, const Eigen::Vector2d& q_meas,
                         const Eigen::Vector2d& qd_ref = Eigen::Vector2d::Zero(), const Eigen::Vector2d& qd_meas = Eigen::Vector2d::Zero()) {
  Eigen::Vector2d u = Eigen::Vector2d::Zero();
  pid.update(q_ref, qd_ref, q_meas, qd_meas, u);
  return u;
}

TEST(PidControllerTest, ProportionalIntegralDerivativeTerms) {
  PidGains g = twoJointGains();
  g.kp_Nm_per_rad = Eigen::Vector2d(100.0, 10.0);
  g.ki_Nm_per_rad_s = Eigen::Vector2d(1000.0, 0.0);
  g.kd_Nms_per_rad = Eigen::Vector2d(2.0, 0.0);
  g.derivative_cutoff_Hz = 0.0;  // plain backward difference
  const double dt = 1e-3;
  PidController pid(g, dt);
  const Eigen::Vector2d ref(0.01, 0.02);
  const Eigen::Vector2d u = feedback(pid, ref, Eigen::Vector2d::Zero(), Eigen::Vector2d(0.5, 0.0));
  // hip: kp e + ki e dt (+ kd de/dt, taken as 0 on the first sample: the controller starts at rest)
  EXPECT_DOUBLE_EQ(u[0], 100 * 0.01 + 1000 * 0.01 * dt);
  EXPECT_DOUBLE_EQ(u[1], 10 * 0.02);
  // measured motion of 1e-3 rad in one step: the error falls by 1e-3 rad, de/dt = -1 rad/s
  const Eigen::Vector2d u2 = feedback(pid, ref, Eigen::Vector2d(1e-3, 0.0));
  EXPECT_NEAR(u2[0], 100 * 0.009 + 1000 * (0.01 + 0.009) * dt + 2 * (-1.0), 1e-12);
}

TEST(PidControllerTest, DisabledJointOutputsZeroAndIntegralIsPreloaded) {
  PidController pid(twoJointGains(), 1e-3);
  pid.reset({false, true}, Eigen::Vector2d(5.0, 7.0));
  const Eigen::Vector2d u = feedback(pid, Eigen::Vector2d(0.3, 0.2), Eigen::Vector2d(0.1, 0.2));
  EXPECT_EQ(u[0], 0.0);
  EXPECT_DOUBLE_EQ(u[1], 7.0);  // zero error: only the preloaded integral
}

TEST(PidControllerTest, IntegralIsClamped) {
  PidGains g = twoJointGains();
  g.integral_limit_Nm = 3.0;
  g.kp_Nm_per_rad.setZero();
  g.kd_Nms_per_rad.setZero();
  PidController only_i(g, 1e-3);
  Eigen::Vector2d u;
  for (int i = 0; i < 1000; ++i) u = feedback(only_i, Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d::Zero());
  EXPECT_DOUBLE_EQ(u[0], 3.0);
}

// The motor rig's law on three joints: the tachometer's velocity error, unfiltered, added to the
// feedforward already in the command.
TEST(PidControllerTest, MeasuredVelocityOnAnyNumberOfJoints) {
  PidGains g;
  g.kp_Nm_per_rad = Eigen::Vector3d(100.0, 50.0, 10.0);
  g.ki_Nm_per_rad_s = Eigen::Vector3d::Zero();
  g.kd_Nms_per_rad = Eigen::Vector3d(5.0, 2.0, 1.0);
  g.derivative = DerivativeSource::kMeasuredVelocity;
  PidController pid(g, 1e-3);
  Eigen::VectorXd command = Eigen::Vector3d(1.0, 2.0, 3.0);
  pid.update(Eigen::Vector3d(0.1, 0.0, -0.1), Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::Vector3d::Zero(), Eigen::Vector3d(0.5, 0.5, 0.0), command);
  EXPECT_EQ(command[0], (1.0 + 100.0 * 0.1) + 5.0 * 0.5);
  EXPECT_EQ(command[1], 2.0 + 2.0 * -0.5);
  EXPECT_EQ(command[2], 3.0 + 10.0 * -0.1);
}

TEST(PidControllerTest, ValidationNamesTheField) {
  PidGains g = twoJointGains();
  g.kd_Nms_per_rad[1] = -1;
  try {
    g.validate({"hip", "knee"});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("gains.kd_Nms_per_rad[knee]"), std::string::npos) << e.what();
  }
  g = twoJointGains();
  g.integral_limit_Nm = 0;
  EXPECT_THROW(g.validate(), std::invalid_argument);
  g = twoJointGains();
  g.ki_Nm_per_rad_s = Eigen::Vector3d::Ones();
  EXPECT_THROW(PidController(g, 1e-3), std::invalid_argument);  // a gain per joint
}

}  // namespace
}  // namespace exoid::core
