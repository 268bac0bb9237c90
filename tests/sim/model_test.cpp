#include "exoid/sim/model.hpp"
#include "exoid/sim/data_dir.hpp"
#include "exoid/sim/serial_chain.hpp"

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

// A file's root element says which reader takes it, not its name: a URDF saved as .xml is read by
// urdfdom, an MJCF saved as .mjcf or .urdf by MuJoCo, and each gives the robot its proper name gives.
TEST_F(ModelTest, TheRootElementNotTheNameSaysUrdfOrMjcf) {
  const std::string urdf = readFileBytes(dataPath("models/leg3.urdf")), mjcf = readFileBytes(dataPath("models/leg3.xml"));
  const auto saved = [](const std::string& name, const std::string& text) {
    const std::string path = test::scratchPath(name);
    std::ofstream(path, std::ios::binary) << text;
    return path;
  };
  // Before the root: a byte-order mark, blank space, a declaration and a comment naming the other
  // root; a DOCTYPE whose internal subset holds a '>' and the other root too (sniffed only: urdfdom
  // reads no DOCTYPE).
  const std::string urdf_body = urdf.substr(urdf.find("<robot"));
  const std::string urdf_as_xml = saved("leg3_urdf.xml", "\xEF\xBB\xBF \n<?xml version=\"1.0\"?>\n<!-- not a <mujoco> -->\n" + urdf_body);
  const std::string with_doctype = saved("doctype.xml", "<!DOCTYPE robot [ <!ENTITY a \"x > <mujoco>\"> ]>\n" + urdf_body);
  EXPECT_TRUE(isUrdfFile(with_doctype));
  std::remove(with_doctype.c_str());
  const std::string mjcf_as_mjcf = saved("leg3.mjcf", "<!-- a <robot> -->\n" + mjcf), mjcf_as_urdf = saved("leg3_mjcf.urdf", mjcf);
  EXPECT_TRUE(isUrdfFile(dataPath("models/leg3.urdf")));
  EXPECT_TRUE(isUrdfFile(urdf_as_xml));
  EXPECT_FALSE(isUrdfFile(dataPath("models/leg3.xml")));
  EXPECT_FALSE(isUrdfFile(mjcf_as_mjcf));
  EXPECT_FALSE(isUrdfFile(mjcf_as_urdf));
  EXPECT_TRUE(isUrdfFile("/nonexistent/leg.URDF"));  // unreadable: its name picks the reader that names the problem
  EXPECT_FALSE(isUrdfFile("/nonexistent/leg.xml"));
  const SerialChain from_urdf = serialChainFromFile(urdf_as_xml), from_mjcf = serialChainFromFile(mjcf_as_urdf);
  ASSERT_EQ(from_urdf.links.size(), 3u);
  ASSERT_EQ(from_mjcf.links.size(), 3u);
  for (std::size_t j = 0; j < 3; ++j) {
    EXPECT_EQ(from_urdf.links[j].joint, serialChainFromFile(dataPath("models/leg3.urdf")).links[j].joint);
    EXPECT_EQ(from_mjcf.links[j].mass_kg, serialChainFromFile(dataPath("models/leg3.xml")).links[j].mass_kg);
  }
  for (const std::string& p : {urdf_as_xml, mjcf_as_mjcf, mjcf_as_urdf}) std::remove(p.c_str());
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
