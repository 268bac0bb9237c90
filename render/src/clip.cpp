#include "exoid/render/clip.hpp"

#include "exoid/core/atomic_file.hpp"
#include "exoid/core/format.hpp"
#include "exoid/render/framing.hpp"
#include "exoid/render/png.hpp"
#include "exoid/render/video_writer.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

namespace exoid::render {

namespace {

const Track& validated(const Track& t) {
  t.validate();
  return t;
}

const ClipOptions& validated(const ClipOptions& o) {
  o.validate();
  return o;
}

// The options with the camera fitted to the track when asked (a private scene: the framing
// poses the leg at many rows before the first frame).
ClipOptions framed(const Track& track, const ClipOptions& o) {
  if (!o.auto_frame) return o;
  const std::unique_ptr<Scene> scene = openScene(o.model_path, track, o.base_motion_gain, o.selection);
  const SweptBox box = sweptBox(*scene, track);
  const bool plots = o.overlay_enabled && o.overlay.plot && track.hasTorque();
  ClipOptions out = o;
  out.render.camera = frameBox(box, o.render.camera, scene->model()->vis.global.fovy,
                               double(o.render.width) / double(o.render.height), plots ? 0.55 : 1.0);
  return out;
}

}  // namespace

void ClipOptions::validate() const {
  render.validate();
  overlay.validate();
  if (!std::isfinite(fps) || fps <= 0.0 || fps > 240.0) {
    throw std::invalid_argument("'fps' must be in (0, 240], got " + core::toText(fps));
  }
  if (!std::isfinite(base_motion_gain) || base_motion_gain < 0.0) {
    throw std::invalid_argument("'base_motion_gain' must be >= 0, got " + core::toText(base_motion_gain));
  }
}

TrackRenderer::TrackRenderer(const Track& track, const ClipOptions& options)
    : track_(validated(track)),
      options_(framed(track_, validated(options))),
      frames_(render::frameCount(track_, options_.fps)),
      scene_(openScene(options_.model_path, track_, options_.base_motion_gain, options_.selection)),
      renderer_(scene_->model(), options_.render) {
  if (options_.overlay_enabled) overlay_.emplace(track_, options_.overlay);
}

double TrackRenderer::frameTime_s(int k) const {
  if (k < 0 || k >= frames_) {
    throw std::invalid_argument("frame " + core::toText(k) + " outside [0, " + core::toText(frames_) + ")");
  }
  return track_.t_s.front() + static_cast<double>(k) / options_.fps;
}

const Image& TrackRenderer::frame(int k) { return drawRow(track_.rowAt(frameTime_s(k))); }

const Image& TrackRenderer::at(double t_s) { return drawRow(track_.rowAt(t_s)); }

const Image& TrackRenderer::drawRow(std::size_t row) {
  scene_->pose(track_, row);
  if (!overlay_) return renderer_.render(scene_->model(), scene_->data(), nullptr);
  const Overlay overlay = overlay_->at(row);
  return renderer_.render(scene_->model(), scene_->data(), &overlay);
}

ClipSummary renderVideo(const Track& track, const ClipOptions& options, const std::string& out_path) {
  const auto t0 = std::chrono::steady_clock::now();
  options.validate();
  track.validate();
  const int frames = frameCount(track, options.fps);
  // Preflight, before the (slow) renderer exists: ffmpeg on PATH, output folder writable, even size.
  requireFfmpeg(options.ffmpeg);
  if (options.render.width % 2 != 0 || options.render.height % 2 != 0) {
    throw std::invalid_argument("video size must be even (H.264 yuv420p), got " + core::toText(options.render.width) +
                                "x" + core::toText(options.render.height));
  }
  core::checkOutputWritable(out_path);

  TrackRenderer source(track, options);
  VideoWriter video(out_path, options.render.width, options.render.height, options.fps, options.ffmpeg);
  for (int k = 0; k < frames; ++k) video.write(source.frame(k));
  video.finish();

  ClipSummary s;
  s.frames = frames;
  s.clip_duration_s = static_cast<double>(frames) / options.fps;
  s.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  s.ms_per_frame = 1e3 * s.wall_time_s / frames;
  s.realtime_ratio = s.wall_time_s / s.clip_duration_s;
  return s;
}

void renderStill(const Track& track, double t_s, const ClipOptions& options, const std::string& out_path) {
  options.validate();
  track.validate();
  track.rowAt(t_s);  // a bad time fails before any rendering
  core::checkOutputWritable(out_path);
  TrackRenderer source(track, options);
  core::writeFileAtomically(out_path, encodePng(source.at(t_s)));
}

}  // namespace exoid::render
