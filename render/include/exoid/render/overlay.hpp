#pragma once
// What is drawn over the 3D view: text lines and live plots (scrolling time windows), built per
// frame from a Track.
#include "exoid/render/track.hpp"

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace exoid::render {

struct PlotLine {
  std::string name;
  std::array<float, 3> rgb{1.0f, 1.0f, 1.0f};
  std::vector<float> x, y;  ///< at most mjMAXLINEPNT (1000) points
};

struct PlotPanel {
  std::string title;
  std::array<double, 2> x_range{0.0, 1.0};
  std::array<double, 2> y_range{-1.0, 1.0};
  std::vector<PlotLine> lines;
};

struct Overlay {
  std::string text_left, text_right;  ///< mjr_overlay columns (top right), lines separated by '\n'
  std::vector<PlotPanel> panels;      ///< drawn stacked in the lower right corner
};

struct OverlayOptions {
  bool text = true;             ///< time, joint angles (deg), torques
  bool plot = true;             ///< torque plots (needs measured torques in the track)
  double plot_window_s = 4.0;   ///< scrolling window shown by the plots, > 0
  int max_plot_points = 400;    ///< per line and window, in [2, 1000] (decimated by stride)
  void validate() const;        ///< throws std::invalid_argument naming the field
};

/// One joint of what the overlay shows: its angle and torques at every sample of the track.
struct OverlayJoint {
  std::string name;                ///< "hip", "knee", "ankle", ...: the lines' and panels' labels
  std::vector<double> q_rad;       ///< the angle (full size)
  std::vector<double> tau_Nm;      ///< measured torque: empty, or full size for every joint
  std::vector<double> tau_pred_Nm;  ///< predicted torque: empty, or full size for every joint (NaN = none at that sample)
};

/// What the overlay of any robot shows, on a uniform time axis: the APAL leg's Track (hip, knee,
/// pedestal) or any serial chain's joints.
struct OverlayTrack {
  std::string title;
  std::vector<double> t_s;
  std::vector<OverlayJoint> joints;
  std::vector<double> base_x_m, base_z_m;  ///< pedestal position: empty, or full size
  std::string torque_name = "measured";
  std::string prediction_name = "identified";
  bool hasTorque() const { return !joints.empty() && !joints.front().tau_Nm.empty(); }
  bool hasPrediction() const { return !joints.empty() && !joints.front().tau_pred_Nm.empty(); }
  bool hasBase() const { return !base_x_m.empty(); }
  /// Throws std::invalid_argument naming the joint and series whose size is not t_s's, or < 2 samples.
  void validate() const;
};

/// The APAL leg's track as the overlay sees it: hip and knee, and the pedestal.
OverlayTrack overlayTrackOf(const Track& track);

/// Builds the overlay of any row of one track: a text line per joint's angle (and torques), and a
/// torque panel per joint. The plots' y ranges are fixed over the whole track (no jumping axes);
/// the x range is [t - window, t] once t > window, else [t0, t0 + window].
class OverlayBuilder {
 public:
  OverlayBuilder(const Track& track, const OverlayOptions& options);
  OverlayBuilder(OverlayTrack track, const OverlayOptions& options);
  Overlay at(std::size_t row) const;

 private:
  OverlayTrack track_;
  OverlayOptions options_;
  std::vector<std::array<double, 2>> y_range_;  // per joint
};

}  // namespace exoid::render
