// A chain other than the APAL leg drawn offscreen (leg3): a still per pose, different poses
// different images, the same pose the same bytes; errors name what is wrong. Its overlay: a text
// line and a torque panel per joint, the APAL leg's overlay being the two-joint case.
#include "exoid/render/robot_clip.hpp"
#include "exoid/sim/model.hpp"

#include <gtest/gtest.h>

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

TEST(ChainClip, StillsFollowThePoseAndRepeatByteForByte) {
  const std::string dir = ::testing::TempDir();
  const std::string model = sim::modelPathFor("leg3");
  const std::vector<std::string> joints = {"hip", "knee", "ankle"};
  Eigen::VectorXd t(3);
  t << 0.0, 1.0, 2.0;
  Eigen::MatrixXd q(3, 3);
  q << 0.0, 0.2, 0.0,  //
      -1.2, 1.5, 0.3,  //
      0.0, 0.2, 0.0;
  ChainClipOptions o;
  o.render.width = 160;
  o.render.height = 120;
  renderChain(model, joints, t, q, dir + "/a.png", o, 0.0);
  renderChain(model, joints, t, q, dir + "/b.png", o, 1.0);
  renderChain(model, joints, t, q, dir + "/c.png", o, 2.0);
  const std::string a = bytesOf(dir + "/a.png"), b = bytesOf(dir + "/b.png"), c = bytesOf(dir + "/c.png");
  EXPECT_GT(a.size(), 1000u);
  EXPECT_NE(a, b);  // the leg moved
  EXPECT_EQ(a, c);  // same pose, same bytes
  EXPECT_THROW(renderChain(model, {"hip", "knee", "toe"}, t, q, dir + "/x.png", o, 0.0), std::invalid_argument);
  EXPECT_THROW(renderChain(model, joints, t, q, dir + "/x.png", o, 5.0), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.png"));
}

// A 3-joint track at 1 kHz: joint j's torque is (j + 1) sin(t), its prediction 0.9 of it.
OverlayTrack threeJointTrack(std::size_t n, bool prediction) {
  OverlayTrack t;
  t.title = "leg3 test";
  for (const char* name : {"hip", "knee", "ankle"}) t.joints.push_back({name, {}, {}, {}});
  for (std::size_t i = 0; i < n; ++i) {
    const double time = 1e-3 * static_cast<double>(i);
    t.t_s.push_back(time);
    for (std::size_t j = 0; j < 3; ++j) {
      t.joints[j].q_rad.push_back(0.1 * static_cast<double>(j));
      t.joints[j].tau_Nm.push_back(static_cast<double>(j + 1) * std::sin(time));
      if (prediction) t.joints[j].tau_pred_Nm.push_back(0.9 * t.joints[j].tau_Nm.back());
    }
  }
  t.prediction_name = "LS";
  return t;
}

TEST(ChainOverlay, ATextLineAndATorquePanelPerJoint) {
  const OverlayBuilder b(threeJointTrack(3000, true), OverlayOptions{});
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
  OverlayTrack bare = threeJointTrack(100, false);
  for (OverlayJoint& j : bare.joints) j.tau_Nm.clear();
  EXPECT_TRUE(OverlayBuilder(bare, OverlayOptions{}).at(50).panels.empty());
  // A series of another length is refused, naming the joint.
  OverlayTrack bad = threeJointTrack(100, true);
  bad.joints[2].tau_pred_Nm.pop_back();
  try {
    OverlayBuilder(bad, OverlayOptions{});
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("ankle predicted torque"), std::string::npos) << e.what();
  }
}

TEST(ChainOverlay, DrawnOverTheStillAndRefusedForAnotherRecord) {
  const std::string dir = ::testing::TempDir();
  const std::string model = sim::modelPathFor("leg3");
  const OverlayTrack track = threeJointTrack(2000, true);
  Eigen::VectorXd t = Eigen::Map<const Eigen::VectorXd>(track.t_s.data(), 2000);
  Eigen::MatrixXd q = Eigen::MatrixXd::Zero(2000, 3);
  ChainClipOptions o;
  o.render.width = 320;
  o.render.height = 240;
  renderChain(model, {"hip", "knee", "ankle"}, t, q, dir + "/plain.png", o, 1.5);
  renderChain(model, {"hip", "knee", "ankle"}, t, q, dir + "/overlay.png", o, 1.5, &track);
  renderChain(model, {"hip", "knee", "ankle"}, t, q, dir + "/overlay2.png", o, 1.5, &track);
  EXPECT_NE(bytesOf(dir + "/plain.png"), bytesOf(dir + "/overlay.png"));
  EXPECT_EQ(bytesOf(dir + "/overlay.png"), bytesOf(dir + "/overlay2.png"));
  const OverlayTrack shorter = threeJointTrack(1000, true);
  EXPECT_THROW(renderChain(model, {"hip", "knee", "ankle"}, t, q, dir + "/y.png", o, 0.5, &shorter), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir + "/y.png"));
}

}  // namespace
}  // namespace exoid::render
