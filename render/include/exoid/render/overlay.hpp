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

/// Builds the overlay of any row of one track: a text line per joint's angle (and torques), and a
/// torque panel per joint. The plots' y ranges are fixed over the whole track (no jumping axes);
/// the x range is [t - window, t] once t > window, else [t0, t0 + window].
class OverlayBuilder {
 public:
  /// Throws std::invalid_argument as Track::validate and OverlayOptions::validate.
  OverlayBuilder(Track track, const OverlayOptions& options);
  Overlay at(std::size_t row) const;

 private:
  Track track_;
  OverlayOptions options_;
  std::vector<std::array<double, 2>> y_range_;  // per joint
};

}  // namespace exoid::render
