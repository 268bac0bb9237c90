#pragma once
// A track rendered frame by frame, for any robot (scene.hpp): to an MP4 (ffmpeg) or to one PNG
// still.
#include "exoid/render/offscreen_renderer.hpp"
#include "exoid/render/overlay.hpp"
#include "exoid/render/scene.hpp"
#include "exoid/render/track.hpp"

#include <memory>
#include <optional>
#include <string>

namespace exoid::render {

struct ClipOptions {
  RenderOptions render;
  OverlayOptions overlay;
  bool overlay_enabled = true;
  double fps = 30.0;                               ///< frames per second, in (0, 240]
  /// The robot's MJCF: the APAL leg's (posed by the track's hip and knee and its pedestal) or any
  /// chain's (posed by the track's joint names).
  std::string model_path = sim::defaultModelPath();
  core::ChainSelection selection;  ///< a URDF's chain (--base, --tip, --lock)
  /// Multiplies the APAL pedestal's mount coordinates when drawing (1 = true size); >= 0.
  double base_motion_gain = 1.0;
  /// Fit the camera to the volume the robot sweeps over the track (render/framing.hpp), so it
  /// stays in frame whatever the motion; with the overlay's plots on, it keeps to the left 55 % of
  /// the image. false: render.camera as given.
  bool auto_frame = true;
  /// ffmpeg executable: a name looked up in PATH, or a path.
  std::string ffmpeg = "ffmpeg";
  void validate() const;  ///< throws std::invalid_argument naming the field and value
};

/// Frame source: a scene posed from the track and a renderer, created once.
class TrackRenderer {
 public:
  /// Validates the track and options; throws like openScene and OffscreenRenderer.
  TrackRenderer(const Track& track, const ClipOptions& options);
  /// The renderer keeps a reference to the track: a temporary would dangle.
  TrackRenderer(Track&& track, const ClipOptions& options) = delete;
  int frameCount() const { return frames_; }
  double frameTime_s(int k) const;
  /// Frame k of the clip (0 <= k < frameCount()). Valid until the next call.
  const Image& frame(int k);
  /// The recorded state nearest to time t (throws std::invalid_argument outside the track).
  const Image& at(double t_s);

 private:
  const Image& drawRow(std::size_t row);
  const Track& track_;
  ClipOptions options_;
  int frames_;
  std::unique_ptr<Scene> scene_;
  OffscreenRenderer renderer_;
  std::optional<OverlayBuilder> overlay_;  // when the options draw it
};

struct ClipSummary {
  int frames = 0;
  double clip_duration_s = 0.0;   ///< frames / fps
  double wall_time_s = 0.0;       ///< setup + rendering + encoding
  double ms_per_frame = 0.0;      ///< wall_time_s / frames
  double realtime_ratio = 0.0;    ///< wall_time_s / clip_duration_s (< 1: faster than real time)
};

/// Renders the whole track to an H.264 MP4 at `out_path`. Checks ffmpeg and the output folder
/// before rendering; writes a temporary file renamed on success. Throws std::runtime_error /
/// std::invalid_argument with a clear message.
ClipSummary renderVideo(const Track& track, const ClipOptions& options, const std::string& out_path);

/// Renders the recorded state nearest to `t_s` to a PNG at `out_path` (atomic). Throws
/// std::invalid_argument for a time outside the track.
void renderStill(const Track& track, double t_s, const ClipOptions& options, const std::string& out_path);

}  // namespace exoid::render
