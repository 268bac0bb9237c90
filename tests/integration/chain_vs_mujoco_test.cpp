// The generic chain regressor (ident/model) on the APAL leg read from its MJCF (sim's serial
// chain, experiments' bridge) times the true standard parameters equals MuJoCo's inverse dynamics
// at random states, friction and armature included: two independent computations of the rig.
#include "exoid/experiments/protocol/robot_loader.hpp"
#include "exoid/ident/model/newton_euler.hpp"
#include "exoid/sim/data_dir.hpp"
#include "exoid/sim/inverse_dynamics.hpp"
#include "exoid/sim/serial_chain.hpp"

#include <gtest/gtest.h>

#include <random>
#include <fstream>
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

namespace {

using namespace exoid;

// The 3-DOF leg: the generic chain read from its MJCF times its true standard parameters equals
// MuJoCo's inverse dynamics (damping and armature inside mj_inverse; the Coulomb term, which the
// simulator applies itself, added as fc sgn(qd)).
TEST(ChainVsMujoco, Leg3WithFrictionAndArmature) {
  const std::string path = sim::modelPathFor("leg3");
  const sim::SerialChain chain = sim::serialChainFromMjcfFile(path);
  ASSERT_EQ(chain.links.size(), 3u);
  EXPECT_EQ(chain.links[2].joint, "ankle");
  EXPECT_EQ(chain.name, "leg3");
  EXPECT_GT(chain.links[2].armature_kgm2, 0.0);
  EXPECT_GT(chain.links[2].coulomb_Nm, 0.0);
  EXPECT_EQ(chain.links[0].q_min_rad, -1.6);  // ranges and motor limits read from the file
  EXPECT_EQ(chain.links[2].tau_max_Nm, 80.0);
  const ident::ChainModel model = experiments::chainModel(chain);
  const Eigen::VectorXd phi = experiments::standardParameters(chain);
  // The file as it is, its stand on the mount (at rest: its springs' deflection and velocity 0).
  const sim::ModelPtr m = sim::loadMjcfFile(path);
  sim::DataPtr d = sim::makeData(m.get());
  const std::vector<int> joints = sim::drivenHinges(m.get(), path);
  mju_zero(d->qacc, m->nv);
  std::mt19937_64 gen(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0;
  for (int k = 0; k < 500; ++k) {
    Eigen::Vector3d q, qd, qdd;
    for (int j = 0; j < 3; ++j) {
      // Inside the joint's range: beyond it mj_inverse adds the limit's constraint force.
      const sim::ChainLinkBody& l = chain.links[static_cast<std::size_t>(j)];
      q[j] = l.q_min_rad + 0.01 + (l.q_max_rad - l.q_min_rad - 0.02) * 0.5 * (1.0 + u(gen));
      qd[j] = 4 * u(gen);
      qdd[j] = 40 * u(gen);
      const int id = joints[static_cast<std::size_t>(j)];
      d->qpos[m->jnt_qposadr[id]] = q[j];
      d->qvel[m->jnt_dofadr[id]] = qd[j];
      d->qacc[m->jnt_dofadr[id]] = qdd[j];
    }
    mj_inverse(m.get(), d.get());
    Eigen::Vector3d theirs;
    for (int j = 0; j < 3; ++j) theirs[j] = d->qfrc_inverse[m->jnt_dofadr[joints[static_cast<std::size_t>(j)]]] + chain.links[static_cast<std::size_t>(j)].coulomb_Nm * ((qd[j] > 0) - (qd[j] < 0));
    const Eigen::Vector3d ours = ident::chainRegressor(model, q, qd, qdd) * phi;
    worst = std::max(worst, (ours - theirs).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-9);  // O(100 N m) torques: roundoff ~1e-13 N m
}

// The URDF beside it holds the same rigid links and friction (no armature: URDF has none).
TEST(ChainVsMujoco, Leg3UrdfEqualsItsMjcf) {
  const sim::SerialChain a = sim::serialChainFromMjcfFile(sim::modelPathFor("leg3"));
  const sim::SerialChain b = sim::serialChainFromUrdf(sim::dataPath("models/leg3.urdf"));
  ASSERT_EQ(a.links.size(), b.links.size());
  for (std::size_t i = 0; i < a.links.size(); ++i) {
    const sim::ChainLinkBody &x = a.links[i], &y = b.links[i];
    EXPECT_EQ(x.joint, y.joint);
    EXPECT_LE((x.parent_R_joint - y.parent_R_joint).norm(), 1e-12) << x.joint;
    EXPECT_LE((x.parent_p_joint_m - y.parent_p_joint_m).norm(), 1e-12) << x.joint;
    EXPECT_LE((x.axis - y.axis).norm(), 1e-12) << x.joint;
    EXPECT_NEAR(x.mass_kg, y.mass_kg, 1e-12) << x.joint;
    EXPECT_LE((x.com_m - y.com_m).norm(), 1e-12) << x.joint;
    EXPECT_LE((x.inertia_com_kgm2 - y.inertia_com_kgm2).norm(), 1e-12) << x.joint;
    EXPECT_EQ(x.coulomb_Nm, y.coulomb_Nm) << x.joint;
    EXPECT_EQ(x.damping_Nms, y.damping_Nms) << x.joint;
  }
}

std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

std::string refusal(const std::string& path) {
  try {
    sim::serialChainFromFile(path);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(ChainVsMujoco, RefusesWhatIsNotASerialRevoluteChainNamingIt) {
  const std::string prismatic = writeTemp("prismatic.urdf", R"(<robot name="r"><link name="a"/><link name="b"/>
    <joint name="slider" type="prismatic"><parent link="a"/><child link="b"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="1" effort="1" velocity="1"/></joint></robot>)");
  EXPECT_NE(refusal(prismatic).find("joint 'slider' is prismatic"), std::string::npos) << refusal(prismatic);
  const std::string floating = writeTemp("floating.urdf", R"(<robot name="r"><link name="a"/><link name="b"/>
    <joint name="base" type="floating"><parent link="a"/><child link="b"/></joint></robot>)");
  EXPECT_NE(refusal(floating).find("floating"), std::string::npos) << refusal(floating);
  const std::string tree = writeTemp("tree.urdf", R"(<robot name="r"><link name="a"/><link name="b"/><link name="c"/>
    <joint name="left" type="continuous"><parent link="a"/><child link="b"/></joint>
    <joint name="right" type="continuous"><parent link="a"/><child link="c"/></joint></robot>)");
  EXPECT_NE(refusal(tree).find("a tree, not a serial chain"), std::string::npos) << refusal(tree);
  const std::string slide = writeTemp("slide.xml", R"(<mujoco><worldbody><body><joint name="s" type="slide"/>
    <geom size="0.1"/></body></worldbody><actuator><motor joint="s"/></actuator></mujoco>)");
  EXPECT_NE(refusal(slide).find("a slide joint"), std::string::npos) << refusal(slide);
}

}  // namespace
