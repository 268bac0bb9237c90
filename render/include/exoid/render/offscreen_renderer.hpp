#pragma once
// Headless rendering with OSMesa (llvmpipe): one object owns the GL context and its buffer, the
// MuJoCo scene, camera, options and render context (docs/mujoco.md notes 9-10: a context must be
// current before mjr_makeContext; never EGL in this target).
#include "exoid/render/image.hpp"
#include "exoid/render/overlay.hpp"

#include <mujoco/mujoco.h>

#include <array>
#include <memory>

namespace exoid::render {

/// Free camera looking along +y (from the right side of the rig, x anterior to the right) at
/// the sagittal x-z plane. The defaults (vertical field of view 45 deg, 4:3) put the rig and the
/// leg's reach (x in [-0.3, 0.75] m, z in [0, 1.3] m for the paper's trajectories) in the left
/// 55 % of the frame; the overlay's text and plots use the right 45 %.
struct CameraOptions {
  std::array<double, 3> lookat{0.62, -0.12, 0.64};  ///< m
  double distance_m = 1.9;
  double azimuth_deg = 90.0;     ///< 90 = looking along +y
  double elevation_deg = -4.0;
};

struct RenderOptions {
  int width = 640;        ///< pixels, in [16, 8192]
  int height = 480;       ///< pixels, in [16, 8192]
  bool shadows = false;   ///< shadow mapping (about twice the cost per frame)
  /// Shadow map side (pixels, m->vis.quality.shadowsize), in [256, 8192]; MuJoCo's default 4096.
  int shadow_map_size = 1024;
  /// Multisample anti-aliasing samples of the offscreen buffer (m->vis.quality.offsamples), in
  /// [0, 8]. Default 0 (slightly jagged edges): on llvmpipe any multisampling about doubles the
  /// cost per frame (measured 11 -> 22 ms at 640x480), which would break real time.
  int multisamples = 0;
  CameraOptions camera;
  void validate() const;  ///< throws std::invalid_argument naming the field and value
};

class OffscreenRenderer {
 public:
  /// Sets m->vis.global.offwidth/offheight (and quality.offsamples, quality.shadowsize) to the
  /// options, creates the OSMesa context,
  /// makes it current and creates the MuJoCo scene and render context for `m`. Throws
  /// std::invalid_argument (bad options) or std::runtime_error ("cannot create the OSMesa ...").
  OffscreenRenderer(mjModel* m, const RenderOptions& options);
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  /// Draws `d` (kinematics already computed) and the overlay, reads the pixels back. The
  /// returned image stays valid until the next call. Makes this context current first, so
  /// several renderers can coexist on one thread.
  const Image& render(const mjModel* m, mjData* d, const Overlay* overlay = nullptr);

  const RenderOptions& options() const { return options_; }

 private:
  struct Impl;
  RenderOptions options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace exoid::render
