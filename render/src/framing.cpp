#include "exoid/render/framing.hpp"

#include "exoid/core/format.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace exoid::render {

namespace {

// Half extents of a geom in its own frame: exact for the primitive shapes the model uses, the
// bounding sphere for anything else (meshes).
std::array<double, 3> halfExtents(const mjModel* m, int g) {
  const mjtNum* s = m->geom_size + 3 * g;
  switch (m->geom_type[g]) {
    case mjGEOM_BOX:
    case mjGEOM_ELLIPSOID: return {s[0], s[1], s[2]};
    case mjGEOM_SPHERE: return {s[0], s[0], s[0]};
    case mjGEOM_CAPSULE: return {s[0], s[0], s[1] + s[0]};
    case mjGEOM_CYLINDER: return {s[0], s[0], s[1]};
    default: {
      const double r = m->geom_rbound[g];
      return {r, r, r};
    }
  }
}

}  // namespace

SweptBox sweptBox(Scene& scene, const Track& track, int samples) {
  track.validate();
  if (samples < 2) throw std::invalid_argument("swept box: need at least 2 samples, got " + core::toText(samples));
  const mjModel* m = scene.model();
  const mjData* d = scene.data();
  const double inf = std::numeric_limits<double>::infinity();
  SweptBox b{inf, -inf, inf, -inf};
  const std::size_t n = track.size();
  for (int k = 0; k < samples; ++k) {
    const auto row = static_cast<std::size_t>(std::llround(double(k) * double(n - 1) / double(samples - 1)));
    scene.pose(track, row);
    for (int g = 0; g < m->ngeom; ++g) {
      if (!scene.framed(g)) continue;
      const std::array<double, 3> h = halfExtents(m, g);
      const mjtNum* R = d->geom_xmat + 9 * g;  // row-major: world = R * local
      // Extent of the rotated box along world x and z: sum of |R_ij| h_j.
      const double ex = std::abs(R[0]) * h[0] + std::abs(R[1]) * h[1] + std::abs(R[2]) * h[2];
      const double ez = std::abs(R[6]) * h[0] + std::abs(R[7]) * h[1] + std::abs(R[8]) * h[2];
      const mjtNum* p = d->geom_xpos + 3 * g;
      b.x_min = std::min(b.x_min, p[0] - ex);
      b.x_max = std::max(b.x_max, p[0] + ex);
      b.z_min = std::min(b.z_min, p[2] - ez);
      b.z_max = std::max(b.z_max, p[2] + ez);
    }
  }
  if (!(b.x_max > b.x_min && b.z_max > b.z_min)) throw std::invalid_argument("swept box: the model has no body geoms");
  return b;
}

CameraOptions frameBox(const SweptBox& box, const CameraOptions& camera, double fovy_deg, double aspect, double width_fraction) {
  if (!(width_fraction > 0.1 && width_fraction <= 1.0)) {
    throw std::invalid_argument("'width_fraction' must be in (0.1, 1], got " + core::toText(width_fraction));
  }
  if (!(fovy_deg > 0.0 && fovy_deg < 180.0) || !(aspect > 0.0)) {
    throw std::invalid_argument("framing: field of view " + core::toText(fovy_deg) + " deg, aspect " + core::toText(aspect));
  }
  // A 5 % margin all round; 8 % more distance for the bodies nearer the camera than the lookat
  // plane (the perspective makes them larger).
  const double tan_half = std::tan(0.5 * fovy_deg * M_PI / 180.0);
  const double width = box.x_max - box.x_min, height = box.z_max - box.z_min;
  const double usable_width = width_fraction - 0.05;
  const double d_height = height / (0.90 * 2.0 * tan_half);
  const double d_width = width / (usable_width * 2.0 * tan_half * aspect);
  CameraOptions out = camera;
  out.distance_m = 1.08 * std::max(d_height, d_width);
  const double view_width = 2.0 * out.distance_m * tan_half * aspect;
  // The box's centre sits at the centre of the image's left width_fraction: the lookat, at the
  // image centre, lies (0.5 - width_fraction / 2) of the view to its right.
  out.lookat[0] = 0.5 * (box.x_min + box.x_max) + (0.5 - 0.5 * width_fraction) * view_width;
  out.lookat[2] = 0.5 * (box.z_min + box.z_max);
  return out;
}

}  // namespace exoid::render
