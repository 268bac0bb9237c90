#pragma once
// The leg model posed for drawing: a private compiled copy of the APAL leg (colors per body
// set on this copy, never in the XML), its data, and the analytic four-bar closure.
#include "exoid/render/scene.hpp"
#include "exoid/sim/four_bar.hpp"
#include "exoid/sim/model.hpp"

#include <array>
#include <cstddef>
#include <optional>
#include <string>

namespace exoid::render {

/// Body colors (RGB). Geoms keep their own alpha (the translucent left leg stays translucent).
struct LegColors {
  std::array<float, 3> pedestal{0.22f, 0.24f, 0.30f};
  std::array<float, 3> trunk{0.68f, 0.70f, 0.74f};
  std::array<float, 3> thigh{0.93f, 0.55f, 0.12f};
  std::array<float, 3> shank{0.20f, 0.68f, 0.32f};
  std::array<float, 3> cylinder{0.18f, 0.38f, 0.88f};
  std::array<float, 3> rod{0.90f, 0.16f, 0.16f};
};

/// One recorded pose: joint angles and (optional) pedestal mount coordinates.
struct Pose {
  double q_hip_rad = 0.0, q_knee_rad = 0.0;
  double base_x_m = 0.0, base_z_m = 0.0, base_pitch_rad = 0.0;
};

/// The pose a track records at `row` (its first two joints: hip, knee), the pedestal's
/// coordinates scaled by `base_motion_gain` (0 when the track has none).
Pose poseAt(const Track& track, std::size_t row, double base_motion_gain = 1.0);

class LegScene final : public Scene {
 public:
  /// Loads `model_path`; `with_mount` keeps the pedestal's mount joints (needed to show pedestal
  /// motion), otherwise the pedestal is welded; a track's pedestal motion is drawn
  /// base_motion_gain times its size. Throws sim::MujocoError / std::invalid_argument.
  LegScene(const std::string& model_path, bool with_mount, double base_motion_gain = 1.0, const LegColors& colors = {});

  /// The track's hip and knee (its first two joints) and pedestal at `row` (setPose(poseAt(...))).
  void pose(const Track& track, std::size_t row) override;
  /// The trunk and all it carries; the pedestal's column and base may leave the frame.
  bool framed(int g) const override;

  /// Sets hip and knee, the passive cylinder/rod joints by the loop closure (zero velocities),
  /// the mount joints (ignored without mount), then computes the kinematics (mj_forward).
  void setPose(const Pose& pose);

  mjModel* model() override { return leg_.model.get(); }
  const mjModel* model() const { return leg_.model.get(); }
  mjData* data() override { return data_.get(); }
  const sim::LegIndices& indices() const { return leg_.idx; }
  bool hasMount() const { return leg_.idx.hasMount(); }

 private:
  sim::LegModel leg_;
  sim::DataPtr data_;
  std::optional<sim::FourBar> four_bar_;
  double base_motion_gain_;
};

}  // namespace exoid::render
