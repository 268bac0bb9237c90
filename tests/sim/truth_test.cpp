#include "exoid/sim/truth.hpp"

#include "test_support.hpp"

#include <urdf_parser/urdf_parser.h>

#include <cstdio>
#include <fstream>

namespace exoid::sim {
namespace {

using test::kTruthTol;

// paper.md "set B": X = [5.83, 2.60, 3.4545, 1.5, 0.6, 1.28, -0.32, 0.5952, 0.35, 0.25].
const ParamArray kSetB = {5.83, 2.60, 3.4545, 1.5, 0.6, 1.28, -0.32, 0.5952, 0.35, 0.25};

// Set B from the physical link values by the paper's corrected Eq. 1 (independent of MuJoCo).
ParamArray setBFromPhysics() {
  const double Lt = 0.45, mt = 13, at = 0.31, ht = 0.20, It = 0.28;
  const double ms = 4, as = 0.32, hs = -0.08, Is = 0.16;
  const double Js = Is + ms * (as * as + hs * hs);
  return {mt * at + ms * Lt, mt * ht, It + mt * (at * at + ht * ht) + ms * Lt * Lt + Js, 1.5, 0.6,
          ms * as, ms * hs, Js, 0.35, 0.25};
}

class TruthTest : public test::MujocoTest {};

void expectParams(const ParamArray& a, const ParamArray& b, double tol) {
  for (int i = 0; i < kNumParams; ++i) EXPECT_NEAR(a[i], b[i], tol) << paramNames()[i];
}

TEST_F(TruthTest, DefaultModelIsSetB) {
  expectParams(setBFromPhysics(), kSetB, 1e-12);
  const Truth t = truthFromModel(defaultModelPath());
  expectParams(t.x, kSetB, kTruthTol);
  EXPECT_NEAR(t.thigh_length_m, 0.45, 1e-15);
  EXPECT_NEAR(t.gravity_mps2, 9.81, 1e-15);
  EXPECT_NEAR(t.thigh_mass_kg, 13.0, 1e-15);
  EXPECT_NEAR(t.shank_mass_kg, 4.0, 1e-15);
}

TEST_F(TruthTest, RigidVariantIsSetB) {
  ModelVariant v;
  v.cylinder_mass_scale = 0.0;
  v.vibration_level = 0.0;
  expectParams(rigidTruth(loadLeg(defaultModelPath(), v)).x, kSetB, kTruthTol);
}

TEST_F(TruthTest, FrictionOverridesEnterTheTruth) {
  ModelVariant v;
  v.fc_knee_Nm = 0.8;
  v.fv_hip_Nms = 1.1;
  const Truth t = rigidTruth(loadLeg(defaultModelPath(), v));
  EXPECT_EQ(t.x[8], 0.8);
  EXPECT_EQ(t.x[4], 1.1);
}

TEST_F(TruthTest, RotatedPrincipalAxesAreHandled) {
  // Same shank, inertia given as a full tensor with an off-diagonal xz term: MuJoCo stores
  // rotated principal axes (body_iquat != identity) but the yy entry about y is still 0.16.
  std::string xml = readFileBytes(defaultModelPath());
  const std::string from = R"(<inertial pos="0.08 0 -0.32" mass="4" diaginertia="0.16 0.16 0.01"/>)";
  const std::string to = R"(<inertial pos="0.08 0 -0.32" mass="4" fullinertia="0.16 0.16 0.01 0 0.004 0"/>)";
  ASSERT_NE(xml.find(from), std::string::npos);
  xml.replace(xml.find(from), from.size(), to);
  const std::string path = test::scratchPath("rotated.xml");
  { std::ofstream(path) << xml; }
  const LegModel leg = loadLeg(path, ModelVariant{}, true);
  const mjtNum* iq = leg.model->body_iquat + 4 * leg.idx.body_shank;
  EXPECT_GT(std::abs(iq[0] - 1.0), 1e-6);  // the test exercises the rotation
  expectParams(rigidTruth(leg).x, kSetB, kTruthTol);
  std::remove(path.c_str());
}

TEST_F(TruthTest, UrdfAndMjcfAgree) {
  const std::string urdf_path = std::string(EXOID_SOURCE_DIR) + "/models/apal_leg.urdf";
  const Truth u = truthFromUrdf(urdf_path);
  const Truth m = truthFromModel(defaultModelPath());
  expectParams(u.x, m.x, 1e-12);
  EXPECT_NEAR(u.thigh_length_m, m.thigh_length_m, 1e-15);

  // Link by link: mass, COM, inertia, and the joint frames.
  const auto model = urdf::parseURDFFile(urdf_path);
  ASSERT_TRUE(model);
  const LegModel leg = loadLeg(defaultModelPath(), ModelVariant{}, true);
  const mjModel* mj = leg.model.get();
  for (const char* name : {"pedestal", "trunk", "thigh", "shank"}) {
    SCOPED_TRACE(name);
    const auto link = model->getLink(name);
    ASSERT_TRUE(link && link->inertial);
    const int b = mj_name2id(mj, mjOBJ_BODY, name);
    ASSERT_GE(b, 0);
    EXPECT_NEAR(link->inertial->mass, mj->body_mass[b], 1e-12);
    const auto& p = link->inertial->origin.position;
    EXPECT_NEAR(p.x, mj->body_ipos[3 * b + 0], 1e-12);
    EXPECT_NEAR(p.y, mj->body_ipos[3 * b + 1], 1e-12);
    EXPECT_NEAR(p.z, mj->body_ipos[3 * b + 2], 1e-12);
    // Both diagonal in the body frame (iquat identity in MuJoCo for diaginertia).
    EXPECT_NEAR(link->inertial->ixx, mj->body_inertia[3 * b + 0], 1e-12);
    EXPECT_NEAR(link->inertial->iyy, mj->body_inertia[3 * b + 1], 1e-12);
    EXPECT_NEAR(link->inertial->izz, mj->body_inertia[3 * b + 2], 1e-12);
    EXPECT_EQ(link->inertial->ixy, 0.0);
    if (std::string(name) != "pedestal") {
      const auto& o = link->parent_joint->parent_to_joint_origin_transform.position;
      EXPECT_NEAR(o.x, mj->body_pos[3 * b + 0], 1e-12);
      EXPECT_NEAR(o.y, mj->body_pos[3 * b + 1], 1e-12);
      EXPECT_NEAR(o.z, mj->body_pos[3 * b + 2], 1e-12);
    }
  }
  for (const char* j : {"hip", "knee"}) {
    const int jid = mj_name2id(mj, mjOBJ_JOINT, j);
    EXPECT_NEAR(model->getJoint(j)->dynamics->damping, mj->dof_damping[mj->jnt_dofadr[jid]], 1e-15);
  }
  EXPECT_NEAR(model->getJoint("hip")->dynamics->friction, leg.coulomb.fc_Nm[0], 1e-15);
  EXPECT_NEAR(model->getJoint("knee")->dynamics->friction, leg.coulomb.fc_Nm[1], 1e-15);
}

TEST_F(TruthTest, BadUrdfNamesTheFile) {
  try {
    truthFromUrdf("/no/such/leg.urdf");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("/no/such/leg.urdf"), std::string::npos);
  }
}

TEST_F(TruthTest, LumpedEqualsRigidWithoutCylinderMass) {
  ModelVariant v;
  v.cylinder_mass_scale = 0.0;
  const LegModel leg = loadLeg(defaultModelPath(), v);
  const ParamBand b = lumpedBand(leg, 0.2, 1.9, 31);
  expectParams(b.min, kSetB, kTruthTol);
  expectParams(b.max, kSetB, kTruthTol);
}

TEST_F(TruthTest, LumpedCylinderMassAddsToTheLinks) {
  const LegModel leg = loadLeg(defaultModelPath());
  const FourBar fb(leg.model.get(), leg.idx);
  DataPtr d = makeData(leg.model.get());
  const ParamArray x0 = lumpedParams(leg, fb, d.get(), 0.0);
  // At q2 = 0 everything hangs straight: cylinder (0.8 kg, COM at (-0.05, -0.22) in the thigh
  // frame) into the thigh, rod (0.4 kg, COM at (-0.05, -0.09 - 0.2 - 0.10) = (-0.05, -0.39) in
  // the thigh frame, i.e. (-0.05, 0.06) relative to the knee) into the shank.
  const double Lt = 0.45, mc = 0.8, mr = 0.4;
  EXPECT_NEAR(x0[5], 1.28 + mr * (-0.06), 1e-12);  // Mxs: rod 6 cm above the knee
  EXPECT_NEAR(x0[6], -0.32 + mr * 0.05, 1e-12);    // Mys: rod 5 cm posterior
  EXPECT_NEAR(x0[0], 5.83 + mc * 0.22 + mr * Lt, 1e-12);
  EXPECT_NEAR(x0[1], 2.60 + mc * 0.05, 1e-12);
  const ParamBand b = lumpedBand(leg, 0.0, 1.8, 19);
  for (int i = 0; i < kNumParams; ++i) EXPECT_LE(b.min[i], b.max[i]);
  EXPECT_GT(b.max[6] - b.min[6], 1e-3);  // Mys moves with the knee angle
}

}  // namespace
}  // namespace exoid::sim

namespace exoid::sim {
namespace {
TEST(UrdfJointLimits, ReadsTheRigsLimits) {
  const UrdfJointLimits l = urdfJointLimits(std::string(EXOID_SOURCE_DIR) + "/models/apal_leg.urdf");
  EXPECT_EQ(l.lower_rad[0], -2.0);
  EXPECT_EQ(l.upper_rad[0], 1.0);
  EXPECT_EQ(l.effort_Nm[0], 300.0);
  EXPECT_EQ(l.velocity_radps[1], 10.0);
  EXPECT_EQ(l.upper_rad[1], 2.2);
  EXPECT_THROW(urdfJointLimits("/no/such/leg.urdf"), std::invalid_argument);
}
}  // namespace
}  // namespace exoid::sim
