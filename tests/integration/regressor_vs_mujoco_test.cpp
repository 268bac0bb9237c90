// The paper's regressor (ident) times X_true (sim, from the compiled model) equals MuJoCo's
// inverse dynamics at random states on the rigid variant (cylinder mass 0, pedestal welded).
#include "exoid/ident/leg/regressor.hpp"
#include "exoid/sim/inverse_dynamics.hpp"
#include "exoid/sim/truth.hpp"

#include <gtest/gtest.h>

#include <random>

namespace {

using namespace exoid;

TEST(RegressorVsMujoco, RigidVariantAtRandomStates) {
  sim::ModelVariant v;
  v.cylinder_mass_scale = 0.0;
  v.vibration_level = 0.0;
  sim::LegModel leg = sim::loadLeg(sim::defaultModelPath(), v);
  const sim::Truth truth = sim::rigidTruth(leg);
  const double v0 = leg.coulomb.v0_radps;
  sim::IdealInverseDynamics inv(std::move(leg));
  ident::ParamVector X;
  for (int i = 0; i < 10; ++i) X[i] = truth.x[static_cast<std::size_t>(i)];
  const ident::LegConstants c{truth.thigh_length_m, truth.gravity_mps2};

  std::mt19937_64 gen(12345);  // test inputs only; any sequence is fine
  std::uniform_real_distribution<double> q(-2.0, 2.0), qd(-4.0, 4.0), qdd(-40.0, 40.0);
  double worst = 0.0;
  for (int k = 0; k < 1000; ++k) {
    Eigen::Vector2d Q(q(gen), q(gen)), Qd(qd(gen), qd(gen)), Qdd(qdd(gen), qdd(gen));
    // Keep |qd| > 20 v0 so fc tanh(qd / v0) = fc sgn(qd) to 2 exp(-40) ~ 1e-17 relative.
    for (int j = 0; j < 2; ++j) {
      if (std::abs(Qd[j]) < 20 * v0) Qd[j] = 20 * v0;
    }
    ident::RegressorRow hip, knee;
    ident::regressorRows(c, Q, Qd, Qdd, hip, knee);
    const Eigen::Vector2d tau = inv.torque(Q, Qd, Qdd);  // mj_inverse + fc tanh(qd/v0)
    worst = std::max({worst, std::abs(hip.dot(X) - tau[0]), std::abs(knee.dot(X) - tau[1])});
  }
  // Torques are O(100 N m); the two computations differ only by roundoff (~1e-13).
  std::printf("[ info ] max |Y X_true - mj_inverse| = %.3g N m over 1000 random states\n", worst);
  EXPECT_LT(worst, 1e-8);
}

}  // namespace

namespace {
TEST(RegressorVsMujoco, KneeArmatureIsIa2OnTheKneeDiagonal) {
  // MuJoCo's armature on the knee dof: mj_inverse = Y X + Ia2 qdd2 (knee row only), with X the
  // rigid truth unchanged and Ia2 what the truth reports.
  using namespace exoid;
  sim::ModelVariant v;
  v.cylinder_mass_scale = 0.0;
  v.vibration_level = 0.0;
  v.fc_hip_Nm = 0.0;
  v.fc_knee_Nm = 0.0;
  v.knee_armature_kgm2 = 0.08;
  sim::LegModel leg = sim::loadLeg(sim::defaultModelPath(), v);
  const sim::Truth truth = sim::rigidTruth(leg);
  EXPECT_EQ(truth.knee_armature_kgm2, 0.08);
  sim::IdealInverseDynamics inv(std::move(leg));
  ident::ParamVector X;
  for (int i = 0; i < 10; ++i) X[i] = truth.x[static_cast<std::size_t>(i)];
  const ident::LegConstants c{truth.thigh_length_m, truth.gravity_mps2};
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0;
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector2d q(2 * u(gen), 2 * u(gen)), qd(4 * u(gen), 4 * u(gen)), qdd(40 * u(gen), 40 * u(gen));
    ident::RegressorRow hip, knee;
    ident::regressorRows(c, q, qd, qdd, hip, knee);
    const Eigen::Vector2d tau = inv.torque(q, qd, qdd);
    worst = std::max({worst, std::abs(hip.dot(X) - tau[0]), std::abs(knee.dot(X) + 0.08 * qdd[1] - tau[1])});
  }
  EXPECT_LT(worst, 1e-8);  // roundoff on O(100 N m) torques
}
}  // namespace
