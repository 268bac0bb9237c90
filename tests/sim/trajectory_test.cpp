#include "exoid/sim/trajectory.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace exoid::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

TEST(TrajectoryTest, PaperTable1InRadians) {
  // Without ramp, the series equals Table 1's formulas.
  for (int id = 1; id <= 4; ++id) {
    const Trajectory tr(paperTrajectory(id), 0.0);
    for (double t : {0.0, 0.1, 0.37, 1.25}) {
      const double s = std::sin(2 * M_PI * t);
      double hip = 0, knee = 0;
      switch (id) {
        case 1: hip = -10; knee = 45 - 30 * s; break;
        case 2: hip = -10; knee = 60 - 30 * s; break;
        case 3: hip = -30 - 30 * s; knee = 75 - 30 * s; break;
        case 4: hip = -45 - 30 * s; knee = 60 + 30 * s; break;
      }
      const JointReference r = tr.at(t);
      EXPECT_NEAR(r.q[0], hip * kDeg, 1e-14) << id;
      EXPECT_NEAR(r.q[1], knee * kDeg, 1e-14) << id;
    }
  }
  EXPECT_EQ(paperTrajectory(1).locked_joints, 1);
  EXPECT_EQ(paperTrajectory(2).locked_joints, 1);
  EXPECT_EQ(paperTrajectory(3).locked_joints, 0);
  EXPECT_THROW(paperTrajectory(5), std::invalid_argument);
  EXPECT_THROW(paperTrajectory(0), std::invalid_argument);
}

TEST(TrajectoryTest, AnalyticDerivativesMatchFiniteDifferences) {
  core::FourierSeries s = core::FourierSeries::still(2, 3, 0.7);
  s.offset_rad << -0.4, 0.9;
  s.a_rad << 0.1, 0.0, -0.05, 0.1, 0.02, 0.0;
  s.b_rad << 0.2, -0.3, 0.03, 0.05, 0.0, 0.0;
  const Trajectory tr(s, 1.0);
  // Central differences, h = 1e-5 s: error ~ h^2 q''' ~ 1e-10 * (2 pi 2.1)^3 * 0.3 ~ 1e-7.
  const double h = 1e-5, tol = 1e-6;
  for (double t : {0.05, 0.5, 0.99, 1.01, 2.3, 7.7}) {
    const JointReference r = tr.at(t), p = tr.at(t + h), n = tr.at(t - h);
    for (int j = 0; j < 2; ++j) {
      EXPECT_NEAR(r.qd[j], (p.q[j] - n.q[j]) / (2 * h), tol) << t;
      EXPECT_NEAR(r.qdd[j], (p.qd[j] - n.qd[j]) / (2 * h), tol * 10) << t;
    }
  }
}

TEST(TrajectoryTest, RampStartsAtRestAndJoinsTheSeries) {
  const double T = 1.0;
  const Trajectory ramped(paperTrajectory(3), T), plain(paperTrajectory(3), 0.0);
  const JointReference r0 = ramped.at(0.0);
  EXPECT_EQ(r0.qd.norm(), 0.0);
  EXPECT_EQ(r0.qdd.norm(), 0.0);
  EXPECT_EQ(r0.q, plain.at(0.0).q);
  for (double t : {T, 1.5, 3.3}) {
    EXPECT_NEAR((ramped.at(t).q - plain.at(t).q).norm(), 0.0, 1e-15);
    EXPECT_NEAR((ramped.at(t).qd - plain.at(t).qd).norm(), 0.0, 1e-12);
  }
  // Continuity of qdd across the end of the ramp.
  EXPECT_NEAR((ramped.at(T - 1e-9).qdd - plain.at(T).qdd).norm(), 0.0, 1e-6);
}

// The series' own checks are core's (FourierSeries.ValidationNamesTheField); the APAL rig's:
// two joints, only the hip locked, a ramp >= 0.
TEST(TrajectoryTest, TheRigTakesHipAndKneeAndAPositiveRamp) {
  EXPECT_THROW(Trajectory(core::FourierSeries::still(3, 1, 1.0), 0.0), std::invalid_argument);
  core::FourierSeries both_locked = core::FourierSeries::still(2, 1, 1.0);
  both_locked.locked_joints = 2;
  EXPECT_THROW(Trajectory(both_locked, 0.0), std::invalid_argument);
  EXPECT_THROW(Trajectory(paperTrajectory(1), -1.0), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::sim
