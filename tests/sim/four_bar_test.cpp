#include "exoid/sim/four_bar.hpp"

#include "test_support.hpp"

#include <cmath>

namespace exoid::sim {
namespace {

class FourBarTest : public test::MujocoTest {};

TEST_F(FourBarTest, AnalyticClosureClosesTheLoopAtAnyKneeAngle) {
  const LegModel leg = loadLeg(defaultModelPath());
  const mjModel* m = leg.model.get();
  DataPtr d = makeData(m);
  const FourBar fb(m, leg.idx);
  double worst = 0;
  for (double q2 = -0.2; q2 <= 2.0; q2 += 0.05) {
    setLegState(m, d.get(), leg.idx, fb, {-0.3, q2}, {0.0, 0.0});
    mj_kinematics(m, d.get());
    worst = std::max(worst, loopError(m, d.get(), leg.idx));
  }
  EXPECT_LT(worst, test::kLoopStartTol_m);
  EXPECT_LT(worst, 1e-12);  // analytic: roundoff only
}

TEST_F(FourBarTest, WithoutClosureTheLoopIsOpen) {
  // The reason setLegState exists (docs/mujoco.md note 3): knee moved, passive joints at 0.
  const LegModel leg = loadLeg(defaultModelPath());
  const mjModel* m = leg.model.get();
  DataPtr d = makeData(m);
  d->qpos[leg.idx.qadr[1]] = 1.0;
  mj_kinematics(m, d.get());
  EXPECT_GT(loopError(m, d.get(), leg.idx), 1e-2);
}

TEST_F(FourBarTest, DerivativesMatchFiniteDifferences) {
  const LegModel leg = loadLeg(defaultModelPath());
  const FourBar fb(leg.model.get(), leg.idx);
  // Central differences with h = 1e-5: truncation h^2 f''' ~ 1e-10, roundoff eps/h ~ 1e-11.
  const double h = 1e-5, tol = 1e-8;
  for (double q2 : {0.0, 0.5, 1.2, 1.8}) {
    const FourBarState s = fb.closure(q2), p = fb.closure(q2 + h), n = fb.closure(q2 - h);
    EXPECT_NEAR(s.dcyl, (p.cyl - n.cyl) / (2 * h), tol);
    EXPECT_NEAR(s.drod, (p.rod - n.rod) / (2 * h), tol);
    EXPECT_NEAR(s.ddcyl, (p.dcyl - n.dcyl) / (2 * h), tol);
    EXPECT_NEAR(s.ddrod, (p.drod - n.drod) / (2 * h), tol);
  }
  const FourBarState z = fb.closure(0.0);
  EXPECT_EQ(z.cyl, 0.0);
  EXPECT_NEAR(z.rod, 0.0, 1e-15);
  // Knee flexion shortens the cylinder (rod retracts): moment arm dl/dq2 < 0 at 90 deg.
  EXPECT_LT(fb.closure(M_PI / 2).drod, 0.0);
}

TEST_F(FourBarTest, ClosureVelocitiesKeepTheLoopClosedToFirstOrder) {
  // With consistent passive velocities the connect's anchor velocities agree: advance the state
  // by dt with those velocities and the loop stays closed to O(dt^2).
  const LegModel leg = loadLeg(defaultModelPath());
  const mjModel* m = leg.model.get();
  DataPtr d = makeData(m);
  const FourBar fb(m, leg.idx);
  setLegState(m, d.get(), leg.idx, fb, {-0.5, 1.0}, {1.0, 2.0});
  const double dt = 1e-4;
  mj_integratePos(m, d->qpos, d->qvel, dt);
  mj_kinematics(m, d.get());
  // O(dt^2 |qd|^2 * 0.5 m) ~ 1e-8 * 4 * 0.5
  EXPECT_LT(loopError(m, d.get(), leg.idx), 2e-8);
}

}  // namespace
}  // namespace exoid::sim
