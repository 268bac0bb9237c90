// Any robot drawn offscreen by the one clip pipeline: the APAL leg (its scene closes the four-bar
// and moves the pedestal) and a chain from its MJCF (leg3, posed by joint name). A still per pose,
// different poses different images, the same pose the same bytes; errors name what is wrong. The
// overlay: a text line and a torque panel per joint, the APAL leg's being the two-joint case.
#include "exoid/render/clip.hpp"
#include "exoid/render/framing.hpp"
#include "exoid/sim/model.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace exoid::render {
namespace {

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The named joints at 1 kHz over n samples: joint j at 0.1 j rad, its torque (j + 1) sin(t) and,
// with a prediction, 0.9 of that.
Track jointsTrack(const std::vector<std::string>& names, std::size_t n, bool prediction) {
  Track t;
  t.title = "test";
  for (const std::string& name : names) t.joints.push_back({name, {}, {}, {}});
  for (std::size_t i = 0; i < n; ++i) {
    const double time = 1e-3 * static_cast<double>(i);
    t.t_s.push_back(time);
    for (std::size_t j = 0; j < names.size(); ++j) {
      t.joints[j].q_rad.push_back(0.1 * static_cast<double>(j));
      t.joints[j].tau_Nm.push_back(static_cast<double>(j + 1) * std::sin(time));
      if (prediction) t.joints[j].tau_pred_Nm.push_back(0.9 * t.joints[j].tau_Nm.back());
    }
  }
  t.prediction_name = "LS";
  return t;
}

struct Robot {
  const char* model;
  std::vector<std::string> joints;
};
const Robot kRobots[] = {{"apal", {"hip", "knee"}}, {"leg3", {"hip", "knee", "ankle"}}};

TEST(RobotClip, StillsFollowThePoseAndRepeatByteForByteOnEveryRobot) {
  const std::string dir = ::testing::TempDir();
  for (const Robot& robot : kRobots) {
    SCOPED_TRACE(robot.model);
    Track t = jointsTrack(robot.joints, 3000, false);
    for (std::size_t i = 1000; i < 2000; ++i) {
      t.joints[0].q_rad[i] = -1.2;
      t.joints[1].q_rad[i] = 1.5;
    }
    ClipOptions o;
    o.model_path = sim::modelPathFor(robot.model);
    o.render.width = 160;
    o.render.height = 120;
    o.overlay_enabled = false;
    renderStill(t, 0.5, o, dir + "/a.png");
    renderStill(t, 1.5, o, dir + "/b.png");
    renderStill(t, 2.5, o, dir + "/c.png");
    const std::string a = bytesOf(dir + "/a.png"), b = bytesOf(dir + "/b.png"), c = bytesOf(dir + "/c.png");
    EXPECT_GT(a.size(), 1000u);
    EXPECT_NE(a, b);  // the leg moved
    EXPECT_EQ(a, c);  // same pose, same bytes
    // The overlay is drawn over the same view, the same way each time.
    o.overlay_enabled = true;
    renderStill(t, 0.5, o, dir + "/overlay.png");
    renderStill(t, 0.5, o, dir + "/overlay2.png");
    EXPECT_NE(bytesOf(dir + "/overlay.png"), a);
    EXPECT_EQ(bytesOf(dir + "/overlay.png"), bytesOf(dir + "/overlay2.png"));
    EXPECT_THROW(renderStill(t, 5.0, o, dir + "/x.png"), std::invalid_argument);
    EXPECT_FALSE(std::filesystem::exists(dir + "/x.png"));
  }
}

TEST(RobotClip, AJointTheChainLacksIsNamed) {
  const std::string dir = ::testing::TempDir();
  ClipOptions o;
  o.model_path = sim::modelPathFor("leg3");
  try {
    renderStill(jointsTrack({"hip", "knee", "toe"}, 100, false), 0.05, o, dir + "/x.png");
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no joint 'toe'"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.png"));
  // The APAL leg is posed by its hip and knee: a track of another robot is refused.
  o.model_path = sim::defaultModelPath();
  EXPECT_THROW(renderStill(jointsTrack({"hip", "knee", "ankle"}, 100, false), 0.05, o, dir + "/x.png"), std::invalid_argument);
}

// leg3's MJCF, and its URDF (no geometry of its own: drawn as a capsule and a sphere a link).
TEST(RobotClip, TheChainsFramingHoldsItsMovingBodies) {
  const Track t = jointsTrack({"hip", "knee", "ankle"}, 100, false);
  for (const std::string& path : {sim::modelPathFor("leg3"), std::string(EXOID_SOURCE_DIR) + "/models/leg3.urdf"}) {
    SCOPED_TRACE(path);
    ChainScene scene(path, {"hip", "knee", "ankle"});
    const SweptBox box = sweptBox(scene, t);
    scene.pose(t, 0);
    const mjModel* m = scene.model();
    for (int b = 1; b < m->nbody; ++b) {
      if (m->body_jntnum[b] == 0 && m->body_parentid[b] == 0) continue;  // a fixed stand may leave the frame
      const double* x = scene.data()->xpos + 3 * b;
      EXPECT_GE(x[0], box.x_min) << mj_id2name(m, mjOBJ_BODY, b);
      EXPECT_LE(x[0], box.x_max) << mj_id2name(m, mjOBJ_BODY, b);
      EXPECT_GE(x[2], box.z_min) << mj_id2name(m, mjOBJ_BODY, b);
      EXPECT_LE(x[2], box.z_max) << mj_id2name(m, mjOBJ_BODY, b);
    }
  }
}

TEST(RobotOverlay, ATextLineAndATorquePanelPerJoint) {
  const OverlayBuilder b(jointsTrack({"hip", "knee", "ankle"}, 3000, true), OverlayOptions{});
  const Overlay o = b.at(2000);
  ASSERT_EQ(o.panels.size(), 3u);
  const char* names[] = {"hip", "knee", "ankle"};
  for (std::size_t j = 0; j < 3; ++j) {
    EXPECT_EQ(o.panels[j].title, std::string(names[j]) + " torque (N m)");
    ASSERT_EQ(o.panels[j].lines.size(), 3u);  // measured, LS, error
    // Measured - predicted at the current sample: 0.1 (j + 1) sin(2).
    EXPECT_NEAR(o.panels[j].lines[2].y.back(), 0.1 * static_cast<double>(j + 1) * std::sin(2.0), 1e-6);
    // Fixed y range over the whole record (t in [0, 3) s: the torque spans [0, j + 1] N m), not the window's.
    EXPECT_LT(o.panels[j].y_range[0], 0.0);
    EXPECT_GT(o.panels[j].y_range[1], static_cast<double>(j + 1));
  }
  EXPECT_NE(o.text_left.find("ankle angle"), std::string::npos) << o.text_left;
  EXPECT_NE(o.text_left.find("ankle torque measured/LS/err"), std::string::npos) << o.text_left;
  EXPECT_NE(o.text_right.find("+5.7 deg"), std::string::npos) << o.text_right;  // the knee's 0.1 rad
  // Without torques: angles only, no panels.
  Track bare = jointsTrack({"hip", "knee", "ankle"}, 100, false);
  for (TrackJoint& j : bare.joints) j.tau_Nm.clear();
  EXPECT_TRUE(OverlayBuilder(bare, OverlayOptions{}).at(50).panels.empty());
  // A series of another length is refused, naming the joint.
  Track bad = jointsTrack({"hip", "knee", "ankle"}, 100, true);
  bad.joints[2].tau_pred_Nm.pop_back();
  try {
    OverlayBuilder(bad, OverlayOptions{});
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("ankle predicted torque"), std::string::npos) << e.what();
  }
}

// From four joints the text gives a line a joint (angle, then torque), so that at the default
// 560 px the torque panels keep room below it: the title, time, a header, 4 joints and the plots'
// legend are 8 lines (two lines a joint: 11, which left the panels no plot area).
TEST(RobotOverlay, FromFourJointsALineAJoint) {
  const Overlay o = OverlayBuilder(jointsTrack({"yaw", "roll", "pitch", "knee"}, 3000, true), OverlayOptions{}).at(2000);
  ASSERT_EQ(o.panels.size(), 4u);
  EXPECT_EQ(std::count(o.text_left.begin(), o.text_left.end(), '\n'), 7) << o.text_left;
  EXPECT_EQ(std::count(o.text_right.begin(), o.text_right.end(), '\n'), 7) << o.text_right;
  EXPECT_NE(o.text_left.find("\njoint\nyaw\nroll\npitch\nknee\n"), std::string::npos) << o.text_left;
  EXPECT_NE(o.text_right.find("\nangle, torque measured/LS/err\n"), std::string::npos) << o.text_right;
  // The knee's 0.3 rad; its torque 4 sin(2), LS 0.9 of it, the error 0.1 of it.
  EXPECT_NE(o.text_right.find("\n+17.2 deg, +3.64 / +3.27 / +0.36 N m"), std::string::npos) << o.text_right;
}

}  // namespace
}  // namespace exoid::render
