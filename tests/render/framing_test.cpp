// The camera fitted to a track keeps the whole leg in view: the box geometry against a pinhole
// projection, and rendered frames of a leg swung far forward checked pixel by pixel.
#include "exoid/render/clip.hpp"
#include "exoid/render/framing.hpp"
#include "exoid/render/leg_scene.hpp"
#include <gtest/gtest.h>

#include <cmath>

namespace exoid::render {
namespace {

// Hip from 0 to hip_end_deg and knee from 0 to knee_end_deg over 2 s at 1 kHz. The default: the
// foot far anterior (hip flexion is negative).
Track wideSwing(double hip_end_deg = -100.0, double knee_end_deg = 120.0) {
  Track t;
  t.joints = {{"hip", {}, {}, {}}, {"knee", {}, {}, {}}};
  for (int i = 0; i < 2000; ++i) {
    const double s = i / 1999.0;
    t.t_s.push_back(1e-3 * i);
    t.joints[0].q_rad.push_back(hip_end_deg * M_PI / 180.0 * s);
    t.joints[1].q_rad.push_back(knee_end_deg * M_PI / 180.0 * s * s);
  }
  return t;
}

TEST(Framing, TheFramedBoxFitsTheLeftPartOfAPinholeView) {
  // Azimuth 90, elevation 0: the camera looks along +y, image right = +x, up = +z. A point at the
  // lookat's depth projects to u = (x - lookat_x) / (D tan(fovy/2) aspect), v likewise in z.
  const SweptBox box{-0.3, 0.9, 0.2, 1.4};
  CameraOptions cam;
  cam.elevation_deg = 0.0;
  const double fovy = 45.0, aspect = 640.0 / 480.0, wf = 0.55;
  const CameraOptions c = frameBox(box, cam, fovy, aspect, wf);
  const double half_h = c.distance_m * std::tan(0.5 * fovy * M_PI / 180.0), half_w = half_h * aspect;
  const double u_min = (box.x_min - c.lookat[0]) / half_w, u_max = (box.x_max - c.lookat[0]) / half_w;
  const double v_min = (box.z_min - c.lookat[2]) / half_h, v_max = (box.z_max - c.lookat[2]) / half_h;
  // In image fractions from the left: [ (u+1)/2 ] within [0, wf]; vertically within 90 %.
  EXPECT_GE((u_min + 1) / 2, 0.0);
  EXPECT_LE((u_max + 1) / 2, wf);
  EXPECT_GE(v_min, -0.9);
  EXPECT_LE(v_max, 0.9);
  EXPECT_EQ(c.lookat[1], cam.lookat[1]);  // depth and angles kept
  EXPECT_EQ(c.azimuth_deg, cam.azimuth_deg);
  EXPECT_THROW(frameBox(box, cam, fovy, aspect, 0.05), std::invalid_argument);
}

TEST(Framing, TheSweptBoxGrowsWithTheMotionAndHoldsTheHangingLeg) {
  LegScene scene(sim::defaultModelPath(), false);
  Track still = wideSwing();
  for (TrackJoint& j : still.joints) j.q_rad.assign(j.q_rad.size(), 0.0);
  const SweptBox hanging = sweptBox(scene, still);
  const SweptBox swing = sweptBox(scene, wideSwing());
  EXPECT_GT(swing.x_max, hanging.x_max + 0.3);  // the foot goes ~0.9 m forward
  EXPECT_LE(swing.z_min, hanging.z_min + 1e-9);
  // The hanging foot (shank body origin 0.45 m below the hip, foot further down) lies inside.
  scene.setPose(Pose{});
  const double* knee = scene.data()->xpos + 3 * scene.indices().body_shank;
  EXPECT_GT(knee[0], hanging.x_min);
  EXPECT_LT(knee[0], hanging.x_max);
  EXPECT_GT(knee[2], hanging.z_min);
  EXPECT_LT(knee[2], hanging.z_max);
}

// Pixels of the shank's green (LegColors::shank, lit): green well above red and blue.
struct GreenPixels {
  int count = 0, on_border = 0, right_of = 0;
};
GreenPixels green(const Image& im, double right_fraction) {
  GreenPixels g;
  for (int y = 0; y < im.height; ++y) {
    for (int x = 0; x < im.width; ++x) {
      const std::uint8_t* p = &im.rgb[3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(im.width) + static_cast<std::size_t>(x))];
      if (!(p[1] > p[0] + 40 && p[1] > p[2] + 40)) continue;
      ++g.count;
      if (x < 2 || y < 2 || x >= im.width - 2 || y >= im.height - 2) ++g.on_border;
      if (x > right_fraction * im.width) ++g.right_of;
    }
  }
  return g;
}

TEST(Framing, AWideSwingStaysInFrameAndLeftOfThePlots) {
  // Forward (foot far anterior) and backward (hip extended 90 deg: the foot ~0.9 m posterior).
  for (const Track& t : {wideSwing(), wideSwing(90.0, 0.0)}) {
    const double end = t.joints[0].q_rad.back() * 180.0 / M_PI;
    ClipOptions bare;
    bare.overlay_enabled = false;
    TrackRenderer framed(t, bare);
    for (double at : {0.0, 1.0, 1.999}) {
      const GreenPixels g = green(framed.at(at), 1.0);
      EXPECT_GT(g.count, 200) << "hip to " << end << " deg, t = " << at;
      EXPECT_EQ(g.on_border, 0) << "hip to " << end << " deg, t = " << at;
    }
    // With the overlay's plots on the right, the leg keeps to the left 55 % (+ the 5 % margin).
    Track with_torque = t;
    for (TrackJoint& j : with_torque.joints) j.tau_Nm.assign(t.size(), 0.0);
    ClipOptions plots;
    plots.overlay.text = false;
    TrackRenderer left(with_torque, plots);
    for (double at : {0.0, 1.0, 1.999}) {
      const GreenPixels g = green(left.at(at), 0.6);
      EXPECT_GT(g.count, 100) << "hip to " << end << " deg, t = " << at;
      EXPECT_EQ(g.on_border, 0) << "hip to " << end << " deg, t = " << at;
      EXPECT_EQ(g.right_of, 0) << "hip to " << end << " deg, t = " << at;
    }
  }
  // The fixed camera does not follow: with the hip extended the foot leaves its view (what the
  // framing is for).
  ClipOptions fixed;
  fixed.overlay_enabled = false;
  fixed.auto_frame = false;
  const Track back = wideSwing(90.0, 0.0);
  TrackRenderer unframed(back, fixed);
  const GreenPixels lost = green(unframed.at(1.999), 1.0);
  EXPECT_TRUE(lost.count == 0 || lost.on_border > 0) << lost.count << " shank pixels, " << lost.on_border << " on the border";
}

}  // namespace
}  // namespace exoid::render
