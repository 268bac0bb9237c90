// A chain out of a tree (ChainSelection: base, tip, locks) and the strict reading of model files.
// The torques of a chosen chain are checked against KDL in tests/python/test_chain_tree_kdl.py;
// here: which joints and bodies each selection gives, that a lock is the joint made fixed at that
// angle, and that every malformed file is refused by name.
#include "exoid/sim/serial_chain.hpp"
#include "exoid/sim/urdf_rig.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>

namespace exoid::sim {
namespace {

const std::string kExo = std::string(EXOID_SOURCE_DIR) + "/tests/data/two_leg_exo.urdf";
const std::string kLeg3 = std::string(EXOID_SOURCE_DIR) + "/models/leg3.urdf";

std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

std::string refusal(const std::string& path, const ChainSelection& selection = {}) {
  try {
    serialChainFromFile(path, selection);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(accepted)";
}

std::vector<std::string> jointsOf(const SerialChain& c) {
  std::vector<std::string> names;
  for (const ChainLinkBody& l : c.links) names.push_back(l.joint);
  return names;
}

TEST(UrdfTree, ATreeWithoutATipIsRefusedWithItsLeafLinks) {
  const std::string why = refusal(kExo);
  EXPECT_NE(why.find("a tree, not a serial chain"), std::string::npos) << why;
  for (const char* leaf : {"l_sole", "r_sole", "l_forearm", "head"}) EXPECT_NE(why.find(leaf), std::string::npos) << why;
}

TEST(UrdfTree, ALegFromThePelvisToTheSoleLeavesTheOtherBranchesOut) {
  const SerialChain c = serialChainFromUrdf(kExo, {"pelvis", "l_sole", {}});
  EXPECT_EQ(jointsOf(c), (std::vector<std::string>{"l_hip_yaw", "l_hip_roll", "l_hip_pitch", "l_knee", "l_ankle_pitch", "l_ankle_roll"}));
  // Hanging from the base: the other leg, the trunk and the prismatic strap (never on the chain).
  for (const char* out : {"r_hip_yaw_link", "torso", "strap"}) {
    EXPECT_NE(std::find(c.left_out.begin(), c.left_out.end(), out), c.left_out.end()) << out;
  }
  // The thigh cuff, fixed on the thigh, rides with it: 5 + 0.4 kg; the sole with the foot.
  EXPECT_NEAR(c.links[2].mass_kg, 5.4, 1e-12);
  EXPECT_NEAR(c.links[5].mass_kg, 1.2, 1e-12);
  EXPECT_NEAR(c.gravity_mps2.z(), -9.81, 1e-15);
}

TEST(UrdfTree, GravityIsInTheBasesFrameWhenTheBaseIsNotTheRoot) {
  // l_thigh hangs from hip_pitch's origin, rolled by 0.05 rad.
  const SerialChain c = serialChainFromUrdf(kExo, {"l_thigh", "l_sole", {}});
  EXPECT_EQ(c.links.front().joint, "l_knee");
  EXPECT_NEAR(c.gravity_mps2.y(), -9.81 * std::sin(0.05), 1e-12);
  EXPECT_NEAR(c.gravity_mps2.z(), -9.81 * std::cos(0.05), 1e-12);
}

TEST(UrdfTree, ABranchOffAChainLinkIsRefusedUnlessLocked) {
  const std::string why = refusal(kExo, {"pelvis", "l_forearm", {}});
  EXPECT_NE(why.find("joint 'head_yaw'"), std::string::npos) << why;
  EXPECT_NE(why.find("--lock head_yaw="), std::string::npos) << why;
  const SerialChain c = serialChainFromUrdf(kExo, {"pelvis", "l_forearm", {{"head_yaw", 0.3}, {"r_shoulder", 0.5}, {"r_elbow", 1.0}}});
  EXPECT_EQ(jointsOf(c), (std::vector<std::string>{"waist", "l_shoulder", "l_elbow"}));
  EXPECT_NEAR(c.links[0].mass_kg, 12.0 + 3.0 + 2.0 + 2.0 + 1.2, 1e-12);  // torso, battery, head, right arm
}

// A lock is the joint made fixed at that angle: the same links to the last digit of the algebra.
TEST(UrdfTree, ALockedJointIsTheSameAsTheJointMadeFixedThere) {
  std::string text = readText(kExo);
  // head_yaw (axis z) at 0.3, r_shoulder and r_elbow (axis y) at 0.5 and 1.0: zero origin rotations.
  const auto fix = [&text](const std::string& joint, const std::string& rpy) {
    const std::regex re("<joint name=\"" + joint + "\" type=\"revolute\">(.*?)rpy=\"0 0 0\"");
    text = std::regex_replace(text, re, "<joint name=\"" + joint + "\" type=\"fixed\">$1rpy=\"" + rpy + "\"");
  };
  fix("head_yaw", "0 0 0.3");
  fix("r_shoulder", "0 0.5 0");
  fix("r_elbow", "0 1 0");
  const SerialChain fixed = serialChainFromUrdf(writeTemp("exo_fixed.urdf", text), {"pelvis", "l_forearm", {}});
  const SerialChain locked = serialChainFromUrdf(kExo, {"pelvis", "l_forearm", {{"head_yaw", 0.3}, {"r_shoulder", 0.5}, {"r_elbow", 1.0}}});
  ASSERT_EQ(fixed.links.size(), locked.links.size());
  for (std::size_t i = 0; i < fixed.links.size(); ++i) {
    EXPECT_NEAR(fixed.links[i].mass_kg, locked.links[i].mass_kg, 1e-12);
    EXPECT_LT((fixed.links[i].com_m - locked.links[i].com_m).norm(), 1e-12);
    EXPECT_LT((fixed.links[i].inertia_com_kgm2 - locked.links[i].inertia_com_kgm2).norm(), 1e-12);
  }
  // The right arm at another angle moves the torso's COM: the lock is used, not ignored.
  const SerialChain other = serialChainFromUrdf(kExo, {"pelvis", "l_forearm", {{"head_yaw", 0.3}, {"r_shoulder", 1.5}, {"r_elbow", 1.0}}});
  EXPECT_GT((other.links[0].com_m - locked.links[0].com_m).norm(), 1e-6);
}

TEST(UrdfTree, SelectionErrorsNameTheOption) {
  EXPECT_NE(refusal(kExo, {"pelvis", "nose", {}}).find("--tip nose"), std::string::npos);
  EXPECT_NE(refusal(kExo, {"l_thigh", "r_sole", {}}).find("is not below --base l_thigh"), std::string::npos);
  EXPECT_NE(refusal(kExo, {"pelvis", "l_sole", {{"elbow", 0.0}}}).find("--lock elbow"), std::string::npos);
  // A lock on the other leg, which the chain leaves out, would be silently unused.
  EXPECT_NE(refusal(kExo, {"pelvis", "l_sole", {{"r_knee", 0.0}}}).find("neither on the chain"), std::string::npos);
}

// The malformed files of issue 37: each refused, naming the file, the element and the value.
TEST(StrictUrdf, MalformedFilesAreRefusedNamingTheElement) {
  const std::string leg3 = readText(kLeg3);
  const auto mutated = [&leg3](const std::string& name, const std::string& from, const std::string& to) {
    std::string t = leg3;
    const std::size_t at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    t.replace(at, from.size(), to);
    return writeTemp(name, t);
  };
  const struct {
    std::string file, expected;
  } cases[] = {
      {mutated("mass_inf.urdf", "<mass value=\"1.09\"/>", "<mass value=\"-inf\"/>"), "Could not parse inertial element for Link [foot]"},
      {mutated("nan_origin.urdf", "origin xyz=\"0.05 0 -0.075\"", "origin xyz=\"0.05 0 -0.075\" rpy=\"nan 0 0\""), "[foot_to_plate]"},
      {mutated("effort.urdf", "effort=\"80\"", "effort=\"-1e308\""), "joint 'ankle' <limit>: effort -1e+308"},
      {mutated("mass.urdf", "<mass value=\"1.09\"/>", "<mass value=\"-1.09\"/>"), "link 'foot' <inertial>: negative mass -1.09"},
      {mutated("inertia.urdf", "ixx=\"0.0012\"", "ixx=\"-0.5\""), "link 'foot' <inertial>: the inertia"},
      {mutated("velocity.urdf", "velocity=\"8\"/>\n    <dynamics", "velocity=\"-8\"/>\n    <dynamics"), "<limit>: velocity -8"},
  };
  for (const auto& c : cases) {
    const std::string why = refusal(c.file);
    EXPECT_NE(why.find(c.file), std::string::npos) << why;
    EXPECT_NE(why.find(c.expected), std::string::npos) << why;
  }
}

// The same selection in an MJCF, by body names; a driven branch off the chain must be locked.
class MjcfTree : public test::MujocoTest {};

// A CAD exporter's <limit lower="0" upper="0" effort="0" velocity="0"> (example-robot-data's
// double pendulum, refused before for its effort 0) is no limit: lower = upper is URDF's own
// default, an effort or velocity of 0 one nobody filled in. A range the wrong way round is refused.
TEST(StrictUrdf, ALimitOfZerosIsNoLimit) {
  const std::string leg3 = readText(kLeg3);
  const std::string knee = "<limit lower=\"0\" upper=\"2.0\" effort=\"120\" velocity=\"8\"/>";
  ASSERT_NE(leg3.find(knee), std::string::npos);
  const auto withKnee = [&](const std::string& name, const std::string& limit) {
    std::string t = leg3;
    t.replace(t.find(knee), knee.size(), limit);
    return writeTemp(name, t);
  };
  const SerialChain c = serialChainFromUrdf(withKnee("zeros.urdf", "<limit lower=\"0\" upper=\"0\" effort=\"0\" velocity=\"0\"/>"));
  ASSERT_EQ(c.links.size(), 3u);
  EXPECT_EQ(c.links[1].q_min_rad, -std::numeric_limits<double>::infinity());
  EXPECT_EQ(c.links[1].q_max_rad, std::numeric_limits<double>::infinity());
  EXPECT_EQ(c.links[1].tau_max_Nm, std::numeric_limits<double>::infinity());
  EXPECT_EQ(c.links[1].qd_max_radps, std::numeric_limits<double>::infinity());
  EXPECT_EQ(c.links[0].tau_max_Nm, 150.0);  // the hip's, given
  // Simulated without a range or a force range on the knee.
  const ModelPtr m = compileMjcf(urdfRigMjcf(c, false), "zeros");
  const int knee_id = mj_name2id(m.get(), mjOBJ_JOINT, "knee"), motor_id = mj_name2id(m.get(), mjOBJ_ACTUATOR, "knee_motor");
  ASSERT_GE(knee_id, 0);
  ASSERT_GE(motor_id, 0);
  EXPECT_EQ(m->jnt_limited[knee_id], 0);
  EXPECT_EQ(m->actuator_forcelimited[motor_id], 0);
  // A range of zero width elsewhere than 0 pins the joint: refused, naming --lock.
  const std::string pinned = refusal(withKnee("pinned.urdf", "<limit lower=\"0.5\" upper=\"0.5\" effort=\"120\" velocity=\"8\"/>"));
  EXPECT_NE(pinned.find("lower = upper = 0.5 rad: a joint that cannot move (hold it with --lock knee=0.5"), std::string::npos) << pinned;
  const std::string reversed = refusal(withKnee("reversed.urdf", "<limit lower=\"2\" upper=\"0\" effort=\"120\" velocity=\"8\"/>"));
  EXPECT_NE(reversed.find("joint 'knee' <limit>: lower 2 rad above upper 0 rad"), std::string::npos) << reversed;
}

// A zero inertia with a round-off residue off its diagonal (iCub's l_ankle_2: ixz 1.35525e-20, the
// rest 0) is zero on the model's scale: read; a moment negative on that scale is still refused.
TEST(StrictUrdf, AnInertiasRoundOffIsJudgedOnTheModelsScale) {
  const std::string leg3 = readText(kLeg3);
  const std::string foot = "ixx=\"0.0012\"";
  ASSERT_NE(leg3.find(foot), std::string::npos);
  const auto withFoot = [&](const std::string& name, const std::string& inertia) {
    std::string t = leg3;
    const std::size_t from = t.rfind("<inertia ", t.find(foot)), to = t.find("/>", from);
    t.replace(from, to - from, "<inertia " + inertia);
    return writeTemp(name, t);
  };
  const SerialChain c = serialChainFromUrdf(withFoot("residue.urdf", "ixx=\"0\" iyy=\"0\" izz=\"0\" ixy=\"0\" ixz=\"1.35525e-20\" iyz=\"0\""));
  // The foot's own inertia gone from the link (the plate fixed below it stays lumped in).
  const Eigen::Matrix3d gone = serialChainFromUrdf(kLeg3).links[2].inertia_com_kgm2 - c.links[2].inertia_com_kgm2;
  EXPECT_LT((gone - Eigen::Vector3d(0.0012, 0.0058, 0.0058).asDiagonal().toDenseMatrix()).norm(), 1e-12) << gone;
  // A moment of -5e-7 kg m^2 on a link of entries 5e-7 is not round-off, whatever the model's scale.
  EXPECT_THROW(serialChainFromUrdf(withFoot("negative.urdf", "ixx=\"0\" iyy=\"0\" izz=\"0\" ixy=\"0\" ixz=\"5e-7\" iyz=\"0\"")),
               std::invalid_argument);
}

TEST_F(MjcfTree, ChainsOutOfAnMjcfTree) {
  const std::string xml = writeTemp("tree.xml", R"(<mujoco model="twoarm"><worldbody><body name="torso" pos="0 0 1">
      <geom size="0.1" mass="5"/>
      <body name="l_upper" pos="0 0.2 0"><joint name="l_sh" axis="0 1 0"/><geom size="0.05" mass="2" pos="0 0 -0.1"/>
        <body name="l_fore" pos="0 0 -0.3"><joint name="l_el" axis="0 1 0"/><geom size="0.04" mass="1" pos="0 0 -0.1"/>
          <body name="l_hand" pos="0 0 -0.25"><joint name="l_wr" axis="1 0 0"/><geom size="0.03" mass="0.5"/></body></body></body>
      <body name="r_upper" pos="0 -0.2 0"><joint name="r_sh" axis="0 1 0"/><geom size="0.05" mass="2" pos="0 0 -0.1"/>
        <body name="r_fore" pos="0 0 -0.3"><joint name="r_el" axis="0 1 0"/><geom size="0.04" mass="1" pos="0 0 -0.1"/></body></body>
    </body></worldbody><actuator><motor joint="l_sh"/><motor joint="l_el"/><motor joint="l_wr"/><motor joint="r_sh"/><motor joint="r_el"/></actuator></mujoco>)");
  const std::string why = refusal(xml);
  EXPECT_NE(why.find("a tree, not a serial chain"), std::string::npos) << why;
  EXPECT_NE(why.find("l_hand"), std::string::npos) << why;
  EXPECT_NE(why.find("r_fore"), std::string::npos) << why;
  EXPECT_EQ(jointsOf(serialChainFromFile(xml, {"torso", "r_fore", {}})), (std::vector<std::string>{"r_sh", "r_el"}));
  const std::string branch = refusal(xml, {"torso", "l_fore", {}});
  EXPECT_NE(branch.find("--lock l_wr="), std::string::npos) << branch;
  const SerialChain c = serialChainFromFile(xml, {"torso", "l_fore", {{"l_wr", 0.4}}});
  EXPECT_EQ(jointsOf(c), (std::vector<std::string>{"l_sh", "l_el"}));
  EXPECT_NEAR(c.links[1].mass_kg, 1.5, 1e-12);  // the hand, locked, rides with the forearm
  // Left out: the right arm, hanging from the base; not the locked hand, which rides with the forearm.
  EXPECT_NE(std::find(c.left_out.begin(), c.left_out.end(), "r_upper"), c.left_out.end());
  EXPECT_EQ(std::find(c.left_out.begin(), c.left_out.end(), "l_hand"), c.left_out.end());
  // A lock on the chain's own path holds that joint: the chain goes on through it.
  const SerialChain held = serialChainFromFile(xml, {"torso", "l_hand", {{"l_el", 0.4}}});
  EXPECT_EQ(jointsOf(held), (std::vector<std::string>{"l_sh", "l_wr"}));
  EXPECT_NEAR(held.links[0].mass_kg, 3.0, 1e-12);  // upper arm and forearm
  // A lock that nothing uses, and one that is not a number, are refused.
  EXPECT_NE(refusal(xml, {"torso", "l_fore", {{"l_wr", 0.4}, {"r_sh", 0.1}}}).find("--lock r_sh"), std::string::npos);
  EXPECT_NE(refusal(xml, {"torso", "l_fore", {{"l_wr", std::nan("")}}}).find("not a finite number"), std::string::npos);
}

// MJCF's strict reading looks at numbers only: a body named "Inf", a comment, a long list are fine.
TEST_F(MjcfTree, StrictReadingLooksAtNumbersOnly) {
  std::string vertices;
  for (int i = 0; i < 20000; ++i) vertices += "ab ";
  const std::string xml = writeTemp("names.xml", R"(<mujoco model="m"><!-- mass="-1" pos="nan 0 0" --><custom><text name="big" data=")" +
                                                     vertices + R"("/></custom><worldbody><body name="Inf" pos="0 0 1">
      <joint name="j" axis="0 1 0"/><geom size="0.1" mass='2'/></body></worldbody><actuator><motor joint="j"/></actuator></mujoco>)");
  EXPECT_EQ(refusal(xml), "(accepted)");
}

// MuJoCo warns of the NaN it reads (hence no warning-free fixture); exoid refuses the file.
TEST(MjcfStrict, ANonFiniteMassIsRefusedByLineAndAttribute) {
  const std::string bad = writeTemp("bad.xml", R"(<mujoco><worldbody><body pos="0 0 1"><joint name="j" axis="0 1 0"/>
      <geom size="0.1" mass='nan'/></body></worldbody><actuator><motor joint="j"/></actuator></mujoco>)");
  EXPECT_NE(refusal(bad).find("mass=\"nan\": a non-finite number"), std::string::npos) << refusal(bad);
}

TEST(StrictUrdf, AZeroAxisIsRefused) {
  std::string text = readText(kLeg3);
  const std::string from = "<axis xyz=\"0 1 0\"/>";
  text.replace(text.find(from), from.size(), "<axis xyz=\"0 0 0\"/>");
  EXPECT_NE(refusal(writeTemp("zero_axis.urdf", text)).find("the zero vector"), std::string::npos);
}

}  // namespace
}  // namespace exoid::sim
