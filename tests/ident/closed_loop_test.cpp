// The closed-loop simulation IDIM-IV draws its instruments from, one for every robot: a PD loop on
// a single inertia against its closed-form frequency response, the forward dynamics against the
// robot's inverse dynamics (the APAL leg's hand-written rows under its rig's PID, a 3-joint chain's
// base regressor under a chain rig's PD with a motor lag), and clear failures for models that
// cannot be simulated.
#include "exoid/ident/model/closed_loop.hpp"
#include "random_chain.hpp"
#include "test_support.hpp"
#include "../support/closed_loop_multisine.hpp"

#include <gtest/gtest.h>

#include <complex>
#include <limits>

namespace exoid::ident {
namespace {


Reference sineReference(double duration_s, double dt_s, double hip0, double hip_amp, double knee0, double knee_amp,
                        double f_hz) {
  const auto n = static_cast<Eigen::Index>(std::llround(duration_s / dt_s)) + 1;
  Reference r;
  r.t_s.resize(n);
  r.q_rad.resize(n, 2);
  r.qd_radps.resize(n, 2);
  r.qdd_radps2.resize(n, 2);
  const double w = 2 * M_PI * f_hz;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * dt_s;
    r.t_s[i] = t;
    r.q_rad.row(i) << hip0 + hip_amp * std::sin(w * t), knee0 + knee_amp * std::sin(w * t);
    r.qd_radps.row(i) << hip_amp * w * std::cos(w * t), knee_amp * w * std::cos(w * t);
    r.qdd_radps2.row(i) << -hip_amp * w * w * std::sin(w * t), -knee_amp * w * w * std::sin(w * t);
  }
  return r;
}

// Knee alone (hip locked), no gravity terms: J qdd + fv qd = kp e + kd de/dt. Closed-form steady
// state: Q / R = (kd s + kp) / (J s^2 + (fv + kd) s + kp) at s = j w.
double maxSteadyStateError(double dt_s) {
  const double J = 0.5, fv = 2.0, kp = 100.0, kd = 10.0, amp = 0.5, f = 1.0;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(kNumParams);
  x[kJs] = J;
  x[kFv2] = fv;
  Controller ctl;
  ctl.kp_Nm_per_rad = Eigen::Vector2d(100.0, kp);
  ctl.kd_Nms_per_rad = Eigen::Vector2d(10.0, kd);
  ctl.feedforward = Feedforward::kNone;
  ctl.locked = {true, false};
  const Reference ref = sineReference(5.0, dt_s, -0.3, 0.0, 0.0, amp, f);
  const ClosedLoopRun run = simulateClosedLoop(twoLinkLeg(test::kLeg), x, ctl, ref);
  EXPECT_TRUE(run.ok) << run.message;
  const double w = 2 * M_PI * f;
  const std::complex<double> s(0.0, w);
  const std::complex<double> G = (kd * s + kp) / (J * s * s + (fv + kd) * s + kp);
  double err = 0.0;
  for (Eigen::Index i = 0; i < ref.size(); ++i) {
    const double t = ref.t_s[i];
    if (t < 3.0) continue;  // transients decay as exp(-(fv + kd) t / 2J) = exp(-12 t): 2e-16 at 3 s
    err = std::max(err, std::abs(run.states.q_rad(i, 1) - amp * std::abs(G) * std::sin(w * t + std::arg(G))));
  }
  return err;
}

TEST(ClosedLoop, PdLoopOnAnInertiaMatchesItsClosedFormResponse) {
  // The discrete loop differs from the continuous one by its sample-and-hold and backward-difference
  // delays (~dt) and the Euler step: first order in dt. So the error halves with dt and is below
  // amp * (fv + kd) / J * dt, the phase a delay of dt costs at the loop's own rate (0.012 at 1e-3 s).
  const double e1 = maxSteadyStateError(1e-3), e2 = maxSteadyStateError(5e-4);
  EXPECT_LT(e1, 0.5 * 24.0 * 1e-3);
  EXPECT_NEAR(e1 / e2, 2.0, 0.2);
}

// A controller file may say the integral has no limit (inf): the rig's PID takes it as the largest.
TEST(ClosedLoop, AnIntegralWithoutLimitRunsAsWithTheLargestLimit) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(kNumParams);
  x[kJs] = 0.5;
  x[kFv2] = 2.0;
  Controller ctl;
  ctl.kp_Nm_per_rad = Eigen::Vector2d(100.0, 100.0);
  ctl.ki_Nm_per_rad_s = Eigen::Vector2d(0.0, 50.0);
  ctl.kd_Nms_per_rad = Eigen::Vector2d(10.0, 10.0);
  ctl.feedforward = Feedforward::kNone;
  ctl.locked = {true, false};
  const Reference ref = sineReference(2.0, 1e-3, -0.3, 0.0, 0.0, 0.5, 1.0);
  ctl.integral_limit_Nm = std::numeric_limits<double>::infinity();
  const ClosedLoopRun unlimited = simulateClosedLoop(twoLinkLeg(test::kLeg), x, ctl, ref);
  ctl.integral_limit_Nm = std::numeric_limits<double>::max();
  const ClosedLoopRun largest = simulateClosedLoop(twoLinkLeg(test::kLeg), x, ctl, ref);
  ASSERT_TRUE(unlimited.ok) << unlimited.message;
  EXPECT_EQ(unlimited.states.q_rad, largest.states.q_rad);
}

TEST(ClosedLoop, ForwardDynamicsInvertTheRegressorsInverseDynamics) {
  const ParamVector x = toParamVector(defaultLeg());
  Controller ctl;
  ctl.kp_Nm_per_rad = Eigen::Vector2d(2200.0, 380.0);
  ctl.ki_Nm_per_rad_s = Eigen::Vector2d(6900.0, 1200.0);
  ctl.kd_Nms_per_rad = Eigen::Vector2d(176.0, 30.0);
  ctl.derivative_cutoff_hz = 100.0;
  const Reference ref = sineReference(4.0, 1e-3, -0.5, -0.5, 1.3, -0.5, 1.0);
  const ClosedLoopRun run = simulateClosedLoop(twoLinkLeg(test::kLeg), x, ctl, ref);
  ASSERT_TRUE(run.ok) << run.message;
  // At every sample the torque that drove the model is its inverse dynamics at the state reached.
  const Eigen::MatrixX2d tau = predictTorque(run.states, x, test::kLeg);
  EXPECT_LT((tau - run.states.tau_Nm).cwiseAbs().maxCoeff(), 1e-9 * run.states.tau_Nm.cwiseAbs().maxCoeff());
  // The same with a knee armature: the knee torque carries Ia2 qdd2 on top.
  Eigen::VectorXd x_geared(kNumParams + 1);
  x_geared << x, 0.1;
  const ClosedLoopRun geared = simulateClosedLoop(twoLinkLeg(test::kLeg, true), x_geared, ctl, ref);
  ASSERT_TRUE(geared.ok) << geared.message;
  Eigen::MatrixX2d tau_geared = predictTorque(geared.states, x, test::kLeg);
  tau_geared.col(1) += 0.1 * geared.states.qdd_radps2.col(1);
  EXPECT_LT((tau_geared - geared.states.tau_Nm).cwiseAbs().maxCoeff(), 1e-9 * geared.states.tau_Nm.cwiseAbs().maxCoeff());
  // With the model's own feedforward only the integration error separates motion and reference:
  // second derivative * dt^2 per step, accumulated over a few samples (a few mrad at most).
  EXPECT_LT((run.states.q_rad - ref.q_rad).cwiseAbs().maxCoeff(), 2e-3);
}

TEST(ClosedLoop, AModelWithoutPositiveInertiaIsRefusedNotIntegrated) {
  Eigen::VectorXd x = toParamVector(defaultLeg());
  x[kJs] = -0.1;
  Controller ctl;
  ctl.kp_Nm_per_rad = Eigen::Vector2d(2200.0, 380.0);
  ctl.kd_Nms_per_rad = Eigen::Vector2d(176.0, 30.0);
  const ClosedLoopRun run = simulateClosedLoop(twoLinkLeg(test::kLeg), x, ctl, sineReference(1.0, 1e-3, -0.5, -0.5, 1.3, -0.5, 1.0));
  EXPECT_FALSE(run.ok);
  EXPECT_NE(run.message.find("not positive definite"), std::string::npos) << run.message;
}

TEST(ClosedLoop, ControllerAndReferenceAreValidated) {
  const std::vector<std::string> joints{"hip", "knee"};
  Controller ctl;
  ctl.kp_Nm_per_rad = Eigen::Vector2d(100.0, 0.0);
  ctl.kd_Nms_per_rad = Eigen::Vector2d(0.0, 0.0);
  test::expectInvalidArgumentMentioning([&] { ctl.validate(joints); }, "kp[knee]");
  ctl.kp_Nm_per_rad = Eigen::Vector2d(100.0, 100.0);
  ctl.kd_Nms_per_rad = Eigen::Vector2d(-1.0, 0.0);
  test::expectInvalidArgumentMentioning([&] { ctl.validate(joints); }, "kd[hip]");
  ctl.kd_Nms_per_rad = Eigen::Vector2d(1.0, 1.0);
  ctl.locked = {true, true};
  test::expectInvalidArgumentMentioning([&] { ctl.validate(joints); }, "every joint is locked");
  ctl.locked = {};
  ctl.kd_Nms_per_rad = Eigen::Vector3d(1.0, 1.0, 1.0);
  test::expectInvalidArgumentMentioning([&] { ctl.validate(joints); }, "'kd' has 3 values; the robot has 2 joints");
  Reference r = sineReference(1.0, 1e-3, 0, 0, 0, 0.1, 1.0);
  r.t_s[5] += 5e-4;
  test::expectInvalidArgumentMentioning([&] { r.validate(); }, "not uniform at sample 5");
  EXPECT_EQ(parseFeedforward("model"), Feedforward::kModel);
  test::expectInvalidArgumentMentioning([] { parseFeedforward("pid"); }, "expected none or model");
}

TEST(ClosedLoop, ReferenceFromAnglesDifferentiatesToFourthOrder) {
  const Reference exact = sineReference(2.0, 1e-3, -0.5, -0.5, 1.3, -0.5, 1.0);
  const Reference r = Reference::fromAngles(exact.t_s, exact.q_rad);
  // Interior error (w dt)^4 / 30 relative: 5e-11 at 1 Hz; the one-sided ends are looser.
  const Eigen::Index n = r.size();
  EXPECT_LT((r.qd_radps - exact.qd_radps).middleRows(4, n - 8).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_LT((r.qdd_radps2 - exact.qdd_radps2).middleRows(4, n - 8).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(ClosedLoop, AChainUnderPdWithAMotorLagObeysItsDynamicsAndTracksItsReference) {
  const testing::ChainUnderPd leg(6.0);
  const ClosedLoopRun run = simulateClosedLoop(leg.robot, leg.theta, leg.controller, leg.reference);
  ASSERT_TRUE(run.ok) << run.message;
  const JointSignals& s = run.states;
  double worst = 0.0, track = 0.0;
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    const Eigen::VectorXd tau = chainRegressor(leg.robot.chain, s.q_rad.row(i).transpose(), s.qd_radps.row(i).transpose(),
                                               s.qdd_radps2.row(i).transpose()) * leg.phi;
    worst = std::max(worst, (tau - s.tau_Nm.row(i).transpose()).cwiseAbs().maxCoeff() / std::max(1.0, tau.cwiseAbs().maxCoeff()));
    track = std::max(track, (s.q_rad.row(i) - leg.reference.q_rad.row(i)).cwiseAbs().maxCoeff());
  }
  // Row k's acceleration is the model's answer to row k's torque (a linear solve: roundoff only).
  EXPECT_LT(worst, 1e-10);
  // The model's own feedforward on the reference: the feedback corrects only the integration's
  // and the motor lag's errors, 10 ms of lag on a < 2 Hz motion.
  EXPECT_LT(track, 0.02);
  // An indefinite model is refused, not integrated.
  Eigen::VectorXd bad = leg.theta;
  for (int i = 0; i < leg.robot.parameters(); ++i) {
    if (leg.robot.names()[static_cast<std::size_t>(i)].find("Iyy") != std::string::npos) bad[i] = -1.0;
  }
  const ClosedLoopRun refused = simulateClosedLoop(leg.robot, bad, leg.controller, leg.reference);
  EXPECT_FALSE(refused.ok);
  EXPECT_NE(refused.message.find("not positive definite"), std::string::npos) << refused.message;
  // Gains no rig has against this inertia (a locked joint's, tuned to a 1e9 kg m^2 lock): refused,
  // not integrated in millions of substeps.
  Controller stiff = leg.controller;
  stiff.kp_Nm_per_rad[0] = 1e12;
  const ClosedLoopRun too_stiff = simulateClosedLoop(leg.robot, leg.theta, stiff, leg.reference);
  EXPECT_FALSE(too_stiff.ok);
  EXPECT_NE(too_stiff.message.find("too stiff"), std::string::npos) << too_stiff.message;
  // With its hip locked the chain's hip follows the reference exactly and its knee and ankle keep
  // their own dynamics (the segmental strategy's stage records).
  Controller locked = leg.controller;
  locked.locked = {true, false, false};
  const ClosedLoopRun held = simulateClosedLoop(leg.robot, leg.theta, locked, leg.reference);
  ASSERT_TRUE(held.ok) << held.message;
  EXPECT_EQ((held.states.q_rad.col(0) - leg.reference.q_rad.col(0)).cwiseAbs().maxCoeff(), 0.0);
}

// The shared closed-loop multisine record (tests/support, also the IDIM-IV benchmark's): the hip
// held where the knee-only record says, the logged angles exactly the run's without noise, and
// the same seed the same bytes, another seed other noise.
TEST(ClosedLoop, TheSharedMultisineRecordIsHeldWhereItSaysAndSeeded) {
  const test::ClosedLoopMultisine knee = test::closedLoopMultisine(2001, test::rigController(true));
  ASSERT_TRUE(knee.run.ok) << knee.run.message;
  EXPECT_EQ((knee.run.states.q_rad.col(0).array() != test::kMultisineHipHold_rad).count(), 0);
  const test::ClosedLoopMultisine both = test::closedLoopMultisine(2001, test::rigController(false));
  ASSERT_TRUE(both.run.ok) << both.run.message;
  EXPECT_EQ(test::measuredMultisine(both, {}, false).q_rad, both.run.states.q_rad);
  const Dataset a = test::measuredMultisine(both, {1e-4, 0.5, 7}, true), b = test::measuredMultisine(both, {1e-4, 0.5, 7}, true);
  EXPECT_EQ(a.q_rad, b.q_rad);
  EXPECT_EQ(a.tau_Nm, b.tau_Nm);
  EXPECT_NE(test::measuredMultisine(both, {1e-4, 0.5, 8}, true).tau_Nm, a.tau_Nm);
  EXPECT_EQ(*a.qdd_radps2, both.run.states.qdd_radps2);
}

}  // namespace
}  // namespace exoid::ident
