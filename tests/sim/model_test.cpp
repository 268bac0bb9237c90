#include "exoid/sim/model.hpp"

#include "test_support.hpp"

#include <cstdio>
#include <fstream>

namespace exoid::sim {
namespace {

using test::MujocoTest;

class ModelTest : public MujocoTest {};

TEST_F(ModelTest, DefaultModelLoadsWithAllNames) {
  const LegModel leg = loadLeg(defaultModelPath(), ModelVariant{});
  EXPECT_TRUE(leg.welded);
  EXPECT_FALSE(leg.idx.hasMount());  // vibration 0: mount joints removed
  EXPECT_EQ(leg.model->nv, 4);       // hip, cylinder_hinge, rod_slide, knee
  EXPECT_EQ(leg.model->nu, 2);
  EXPECT_EQ(leg.coulomb.fc_Nm[0], 1.5);
  EXPECT_EQ(leg.coulomb.fc_Nm[1], 0.35);
  EXPECT_EQ(leg.model->dof_armature[leg.idx.vadr[1]], 0.0);
  EXPECT_EQ(leg.xml_fnv1a64, fnv1a64(readFileBytes(defaultModelPath())));
}

TEST_F(ModelTest, MissingFileNamesThePath) {
  const std::string path = "/nonexistent/dir/leg.xml";
  try {
    loadLeg(path);
    FAIL() << "expected an exception";
  } catch (const MujocoError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_THROW(loadMjcfFile(path), MujocoError);
}

TEST_F(ModelTest, InvalidXmlCarriesMujocosMessage) {
  const std::string path = test::scratchPath("bad.xml");
  {
    std::ofstream out(path);
    out << "<mujoco><worldbody><body name='a'><geom type='sphere' size='0.1'/></worldbody></mujoco>";
  }
  try {
    loadMjcfFile(path);
    FAIL() << "expected an exception";
  } catch (const MujocoError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find("MuJoCo could not load the model: "), std::string::npos) << msg;
    // MuJoCo's own text follows (it names the XML problem).
    EXPECT_GT(msg.size(), msg.find(": ", msg.find("model")) + 10) << msg;
  }
  std::remove(path.c_str());
}

TEST_F(ModelTest, CompileErrorFromMemoryNamesTheSource) {
  try {
    compileMjcf("<mujoco><worldbody><geom type='bogus'/></worldbody></mujoco>", "inline model");
    FAIL();
  } catch (const MujocoError& e) {
    EXPECT_NE(std::string(e.what()).find("inline model"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("bogus"), std::string::npos) << e.what();
  }
}

TEST_F(ModelTest, StripMountJointsRemovesOnlyMountJoints) {
  const std::string xml = R"(<body><joint name="a" class="mount" type="slide"/><joint name="b"/>
<joint name="c" class="mount" axis="0 1 0"/></body>)";
  EXPECT_EQ(stripMountJoints(xml, "x"), "<body><joint name=\"b\"/>\n</body>");
  EXPECT_THROW(stripMountJoints("<joint name=\"b\"/>", "x"), std::invalid_argument);
  EXPECT_THROW(stripMountJoints("<joint class=\"mount\"></joint>", "x"), std::invalid_argument);
}

TEST_F(ModelTest, VibrationLevelScalesTheMount) {
  ModelVariant v;
  v.vibration_level = 2.0;
  const LegModel soft = loadLeg(defaultModelPath(), v);
  const ModelPtr raw = loadMjcfFile(defaultModelPath());
  ASSERT_TRUE(soft.idx.hasMount());
  for (int k = 0; k < 3; ++k) {
    const int j = soft.idx.mount_jnt[k];
    EXPECT_DOUBLE_EQ(soft.model->jnt_stiffness[j], raw->jnt_stiffness[j] / 4.0);
    EXPECT_DOUBLE_EQ(soft.model->dof_damping[soft.idx.mount_vadr[k]], raw->dof_damping[soft.idx.mount_vadr[k]] / 2.0);
  }
  EXPECT_EQ(soft.model->nv, 7);
}

TEST_F(ModelTest, CylinderMassScaleZeroMakesTheLoopKinematic) {
  ModelVariant v;
  v.cylinder_mass_scale = 0.0;
  const LegModel leg = loadLeg(defaultModelPath(), v);
  EXPECT_TRUE(leg.kinematic_loop);
  EXPECT_EQ(leg.model->body_mass[leg.idx.body_cylinder], 0.0);
  EXPECT_EQ(leg.model->body_mass[leg.idx.body_rod], 0.0);
  EXPECT_EQ(leg.model->eq_active[leg.idx.eq_loop], 0);
  v.cylinder_mass_scale = 2.0;
  const LegModel heavy = loadLeg(defaultModelPath(), v);
  EXPECT_DOUBLE_EQ(heavy.model->body_mass[heavy.idx.body_cylinder], 1.6);
  EXPECT_EQ(heavy.model->eq_active[heavy.idx.eq_loop], 1);
}

TEST_F(ModelTest, FrictionOverrides) {
  ModelVariant v;
  v.fc_hip_Nm = 2.0;
  v.fv_knee_Nms = 0.4;
  const LegModel leg = loadLeg(defaultModelPath(), v);
  EXPECT_EQ(leg.coulomb.fc_Nm[0], 2.0);
  EXPECT_EQ(leg.coulomb.fc_Nm[1], 0.35);
  EXPECT_EQ(leg.model->dof_damping[leg.idx.vadr[1]], 0.4);
  EXPECT_EQ(leg.model->dof_damping[leg.idx.vadr[0]], 0.6);
}

TEST_F(ModelTest, VariantValidationNamesTheField) {
  ModelVariant v;
  v.cylinder_mass_scale = -1;
  try {
    v.validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'cylinder_mass_scale'"), std::string::npos);
  }
  v = {};
  v.fv_hip_Nms = -0.1;
  EXPECT_THROW(v.validate(), std::invalid_argument);
  v = {};
  v.vibration_level = std::nan("");
  EXPECT_THROW(v.validate(), std::invalid_argument);
}

TEST_F(ModelTest, SmoothCoulombMatchesSignAwayFromZero) {
  CoulombFriction c;
  c.fc_Nm = {1.5, 0.35};
  c.v0_radps = 2e-3;
  // |tanh(x) - sgn(x)| < 2 exp(-2x): at qd = 10 v0 below 2 exp(-20) = 4e-9 relative.
  EXPECT_NEAR(c.torque(0, 10 * c.v0_radps), 1.5, 1.5 * 2 * std::exp(-20.0));
  EXPECT_NEAR(c.torque(1, -0.5), -0.35, 1e-15);
  EXPECT_EQ(c.torque(0, 0.0), 0.0);
}

TEST_F(ModelTest, FnvHashKnownValues) {
  // FNV-1a 64 reference values: "" -> offset basis, "a" -> 0xaf63dc4c8601ec8c.
  EXPECT_EQ(toHex(fnv1a64("")), "cbf29ce484222325");
  EXPECT_EQ(toHex(fnv1a64("a")), "af63dc4c8601ec8c");
}

}  // namespace
}  // namespace exoid::sim
