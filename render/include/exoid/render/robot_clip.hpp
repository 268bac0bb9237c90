#pragma once
// Any serial chain's record drawn offscreen: the MJCF's driven hinges posed by name along the
// recorded angles, the camera fitted to the volume the links sweep, a PNG of one instant or an
// H.264 MP4 of the whole record, with the overlay of clip.hpp (a text line per joint, a torque
// panel per joint) when its track is given.
#include "exoid/render/offscreen_renderer.hpp"
#include "exoid/render/overlay.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace exoid::render {

struct ChainClipOptions {
  RenderOptions render;
  double fps = 30.0;             ///< (0, 240]
  std::string ffmpeg = "ffmpeg";
  bool auto_frame = true;        ///< fit the camera to the swept volume (else render.camera as given)
  OverlayOptions overlay;        ///< what the overlay draws, when renderChain is given its track
  void validate() const;         ///< throws std::invalid_argument naming the field
};

/// q_rad: rows x joints.size() at times t_s; joints named as in the MJCF. frame_s given: the row
/// nearest it as a PNG at out; else every 1 / fps of the record as an MP4. Written atomically.
/// overlay (optional): drawn over every frame, its rows the record's (same time axis). Throws
/// std::invalid_argument (a joint the model lacks, sizes, an instant outside the record),
/// sim::MujocoError, or std::runtime_error (ffmpeg).
void renderChain(const std::string& model_path, const std::vector<std::string>& joints, const Eigen::VectorXd& t_s,
                 const Eigen::MatrixXd& q_rad, const std::string& out, const ChainClipOptions& options,
                 std::optional<double> frame_s = std::nullopt, const OverlayTrack* overlay = nullptr);

}  // namespace exoid::render
