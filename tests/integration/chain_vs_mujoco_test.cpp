// The generic chain regressor (ident/model) on the APAL leg read from its MJCF (sim's serial
// chain, experiments' bridge) times the true standard parameters equals MuJoCo's inverse dynamics
// at random states, friction and armature included: two independent computations of the rig.
#include "exoid/experiments/chain_bridge.hpp"
#include "exoid/ident/model/chain_regressor.hpp"
#include "exoid/sim/inverse_dynamics.hpp"
#include "exoid/sim/serial_chain.hpp"

#include <gtest/gtest.h>

#include <random>
#include <sstream>

namespace {

using namespace exoid;

void expectEqualsMjInverse(const sim::ModelVariant& v, std::uint64_t seed) {
  sim::LegModel leg = sim::loadLeg(sim::defaultModelPath(), v);
  const sim::SerialChain chain = sim::serialChain(leg);
  ASSERT_EQ(chain.links.size(), 2u);
  EXPECT_EQ(chain.links[0].joint, "hip");
  EXPECT_EQ(chain.links[1].joint, "knee");
  const ident::ChainModel model = experiments::chainModel(chain);
  const Eigen::VectorXd phi = experiments::standardParameters(chain);
  const double v0 = leg.coulomb.v0_radps;
  sim::IdealInverseDynamics inv(std::move(leg));
  std::mt19937_64 gen(seed);  // test inputs only
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0;
  for (int k = 0; k < 500; ++k) {
    Eigen::Vector2d q(2 * u(gen), 2 * u(gen)), qd(4 * u(gen), 4 * u(gen)), qdd(40 * u(gen), 40 * u(gen));
    // |qd| > 20 v0: the rig's fc tanh(qd / v0) is fc sgn(qd) to 2 exp(-40) ~ 1e-17 relative.
    for (int j = 0; j < 2; ++j) {
      if (std::abs(qd[j]) < 20 * v0) qd[j] = 20 * v0;
    }
    const Eigen::Vector2d ours = ident::chainRegressor(model, q, qd, qdd) * phi;
    const Eigen::Vector2d theirs = inv.torque(q, qd, qdd);
    worst = std::max(worst, (ours - theirs).cwiseAbs().maxCoeff());
  }
  // Torques are O(100 N m): roundoff is ~1e-13 N m; 1e-8 leaves margin and nothing more (a wrong
  // term is O(1 N m)).
  std::ostringstream text;
  text << std::scientific << worst;
  ::testing::Test::RecordProperty("max_abs_difference_Nm", text.str());
  EXPECT_LT(worst, 1e-8);
}

TEST(ChainVsMujoco, ApalLegRigidWithFriction) {
  sim::ModelVariant v;
  v.cylinder_mass_scale = 0.0;
  v.vibration_level = 0.0;
  expectEqualsMjInverse(v, 3);
}

TEST(ChainVsMujoco, ApalLegWithKneeArmature) {
  sim::ModelVariant v;
  v.cylinder_mass_scale = 0.0;
  v.vibration_level = 0.0;
  v.knee_armature_kgm2 = 0.08;
  expectEqualsMjInverse(v, 4);
}

TEST(ChainVsMujoco, TheFourBarsBodiesAreNamedAsLeftOut) {
  sim::ModelVariant v;
  v.cylinder_mass_scale = 0.0;
  const sim::SerialChain chain = sim::serialChain(sim::loadLeg(sim::defaultModelPath(), v));
  EXPECT_FALSE(chain.left_out.empty());
}

}  // namespace
