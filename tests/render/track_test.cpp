// Track validation, frame counts and the row shown at a time.
#include "exoid/render/overlay.hpp"
#include "exoid/render/track.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace exoid::render {
namespace {

Track uniformTrack(std::size_t n, double dt, bool torque = true) {
  Track t;
  t.joints = {{"hip", {}, {}, {}}, {"knee", {}, {}, {}}};
  for (std::size_t i = 0; i < n; ++i) {
    const double ti = static_cast<double>(i) * dt;
    t.t_s.push_back(ti);
    t.joints[0].q_rad.push_back(-0.5 - 0.5 * std::sin(2 * M_PI * ti));
    t.joints[1].q_rad.push_back(1.3 - 0.5 * std::sin(2 * M_PI * ti));
    if (torque) {
      t.joints[0].tau_Nm.push_back(10 * std::sin(2 * M_PI * ti));
      t.joints[1].tau_Nm.push_back(3 * std::cos(2 * M_PI * ti));
    }
  }
  return t;
}

TEST(Track, FrameCountOfA2sRecordAt30fpsIs60) {
  const Track t = uniformTrack(2000, 1e-3);  // 1 kHz, 2 s
  EXPECT_DOUBLE_EQ(t.duration_s(), 2.0);
  EXPECT_EQ(frameCount(t, 30.0), 60);
  EXPECT_EQ(frameCount(t, 25.0), 50);
  EXPECT_THROW(frameCount(t, 0.0), std::invalid_argument);
  EXPECT_THROW(frameCount(uniformTrack(10, 1e-3), 30.0), std::invalid_argument);  // 10 ms < 1 frame
}

TEST(Track, RowAtIsTheNearestSample) {
  const Track t = uniformTrack(2000, 1e-3);
  EXPECT_EQ(t.rowAt(0.0), 0u);
  EXPECT_EQ(t.rowAt(1.0 / 30.0), 33u);    // 33.3 ms
  EXPECT_EQ(t.rowAt(59.0 / 30.0), 1967u); // 1966.7 ms
  EXPECT_EQ(t.rowAt(1.9996), 1999u);      // clamped to the last row
  EXPECT_THROW(t.rowAt(-0.001), std::invalid_argument);
  EXPECT_THROW(t.rowAt(2.0), std::invalid_argument);
  EXPECT_THROW(t.rowAt(NAN), std::invalid_argument);
}

TEST(Track, ValidateNamesTheProblem) {
  Track t = uniformTrack(100, 1e-3);
  t.joints[1].q_rad.pop_back();
  try {
    t.validate();
    FAIL() << "expected invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("knee angle"), std::string::npos) << e.what();
  }
  t = uniformTrack(100, 1e-3);
  t.t_s[50] += 0.5e-3;
  EXPECT_THROW(t.validate(), std::invalid_argument);
  t = uniformTrack(100, 1e-3);
  t.base_x_m.assign(100, 0.0);  // base_z, base_pitch missing
  EXPECT_THROW(t.validate(), std::invalid_argument);
  t = uniformTrack(100, 1e-3, false);
  for (TrackJoint& j : t.joints) j.tau_pred_Nm.assign(100, 0.0);
  EXPECT_THROW(t.validate(), std::invalid_argument);  // a prediction needs the measured torques
  t = uniformTrack(100, 1e-3);
  t.joints.clear();
  EXPECT_THROW(t.validate(), std::invalid_argument);
}

TEST(Overlay, ScrollingWindowAndPointBudget) {
  Track t = uniformTrack(6000, 1e-3);
  for (TrackJoint& j : t.joints) j.tau_pred_Nm = j.tau_Nm;
  OverlayOptions o;
  o.plot_window_s = 4.0;
  o.max_plot_points = 400;
  const OverlayBuilder b(t, o);
  const Overlay early = b.at(1000);  // t = 1 s: window [0, 4]
  ASSERT_EQ(early.panels.size(), 2u);
  EXPECT_DOUBLE_EQ(early.panels[0].x_range[0], 0.0);
  EXPECT_DOUBLE_EQ(early.panels[0].x_range[1], 4.0);
  const Overlay late = b.at(5500);  // t = 5.5 s: window [1.5, 5.5]
  EXPECT_NEAR(late.panels[1].x_range[0], 1.5, 1e-12);
  EXPECT_NEAR(late.panels[1].x_range[1], 5.5, 1e-12);
  ASSERT_EQ(late.panels[0].lines.size(), 3u);  // measured, prediction, error
  for (const PlotPanel& p : late.panels) {
    for (const PlotLine& l : p.lines) {
      EXPECT_LE(l.x.size(), 400u);
      EXPECT_GE(l.x.front(), p.x_range[0] - 1e-6);
      EXPECT_FLOAT_EQ(l.x.back(), 5.5f);  // ends at the current sample
    }
  }
  // The error line is measured - predicted: zero here. y ranges cover the whole record.
  for (float e : late.panels[0].lines[2].y) EXPECT_EQ(e, 0.0f);
  EXPECT_LT(late.panels[0].y_range[0], -10.0);
  EXPECT_GT(late.panels[0].y_range[1], 10.0);
  EXPECT_NE(late.text_right.find("5.500 s"), std::string::npos) << late.text_right;
}

}  // namespace
}  // namespace exoid::render

namespace exoid::render {
namespace {

TEST(Overlay, PredictionMissingAtTrimmedEdgesIsSkipped) {
  Track t = uniformTrack(3000, 1e-3);
  for (TrackJoint& j : t.joints) {
    j.tau_pred_Nm.assign(3000, NAN);
    for (std::size_t i = 500; i < 2500; ++i) j.tau_pred_Nm[i] = 0.0;
  }
  EXPECT_NO_THROW(t.validate());  // NaN only allowed in the prediction columns
  const OverlayBuilder b(t, OverlayOptions{});
  const Overlay o = b.at(2999);
  for (const PlotPanel& p : o.panels) {
    for (std::size_t l = 1; l < p.lines.size(); ++l) {
      for (float v : p.lines[l].y) EXPECT_FALSE(std::isnan(v));
      EXPECT_LE(p.lines[l].x.back(), 2.5f);
    }
  }
  EXPECT_NE(o.text_right.find("n/a"), std::string::npos);
  t.joints[0].tau_Nm[3] = NAN;
  EXPECT_THROW(t.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::render
