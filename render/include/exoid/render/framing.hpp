#pragma once
// A camera that keeps the whole leg in view over a track: the volume the rig's bodies sweep in
// the sagittal plane, fitted into a chosen part of the image (the overlay's plots take the
// right-hand side).
#include "exoid/render/leg_scene.hpp"
#include "exoid/render/offscreen_renderer.hpp"
#include "exoid/render/track.hpp"

#include <array>

namespace exoid::render {

/// World x (anterior) and z (up) extents of every geom of the trunk and the bodies below it (the
/// leg, the cylinder and rod; not the pedestal), over `samples` rows of the track spread evenly,
/// first and last included.
struct SweptBox {
  double x_min = 0.0, x_max = 0.0, z_min = 0.0, z_max = 0.0;
};
SweptBox sweptBox(LegScene& scene, const Track& track, double base_motion_gain = 1.0, int samples = 240);

/// The camera of `camera` (azimuth, elevation, lookat's y kept) moved so that `box` fills at
/// most `width_fraction` of the image width from the left and 90 % of its height, for a
/// vertical field of view `fovy_deg` and the image's aspect ratio width / height.
/// width_fraction in (0.1, 1]; throws std::invalid_argument otherwise.
CameraOptions frameBox(const SweptBox& box, const CameraOptions& camera, double fovy_deg, double aspect,
                       double width_fraction);

}  // namespace exoid::render
