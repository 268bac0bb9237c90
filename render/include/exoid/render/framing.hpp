#pragma once
// A camera that keeps the whole robot in view over a track: the volume its bodies sweep in
// the sagittal plane, fitted into a chosen part of the image (the overlay's plots take the
// right-hand side).
#include "exoid/render/offscreen_renderer.hpp"
#include "exoid/render/scene.hpp"
#include "exoid/render/track.hpp"

#include <array>

namespace exoid::render {

/// World x (anterior) and z (up) extents of the scene's framed geoms (Scene::framed: the APAL leg's
/// trunk and all below it, not the pedestal; a chain's moving bodies), over `samples` rows of the
/// track spread evenly, first and last included.
struct SweptBox {
  double x_min = 0.0, x_max = 0.0, z_min = 0.0, z_max = 0.0;
};
SweptBox sweptBox(Scene& scene, const Track& track, int samples = 240);

/// The camera of `camera` (azimuth, elevation, lookat's y kept) moved so that `box` fills at
/// most `width_fraction` of the image width from the left and 90 % of its height, for a
/// vertical field of view `fovy_deg` and the image's aspect ratio width / height.
/// width_fraction in (0.1, 1]; throws std::invalid_argument otherwise.
CameraOptions frameBox(const SweptBox& box, const CameraOptions& camera, double fovy_deg, double aspect,
                       double width_fraction);

}  // namespace exoid::render
