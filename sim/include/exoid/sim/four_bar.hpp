#pragma once
// The knee's hydraulic four-bar (thigh - cylinder - rod - shank) closed analytically.
//
// In the thigh frame (x, z plane): C = cylinder hinge (body_pos of `cylinder`), K = knee
// (body_pos of `shank`), D = rod-end anchor on the shank (the loop connect's second anchor, in
// the shank frame). With r(q2) = K + R(q2) D - C and p = the rod end in the cylinder frame at
// rod_slide = 0 (which must lie on the slide axis), the passive coordinates are
//   cylinder_hinge = psi(r) - psi(p),  rod_slide = |r| - |p|,   psi(v) = atan2(v_x, v_z)
// (a rotation by a about +y adds a to psi). Both depend on the knee angle q2 only.
#include "exoid/sim/model.hpp"

#include <mujoco/mujoco.h>

#include <array>

namespace exoid::sim {

/// Passive joint values and their first/second derivatives with respect to q2.
struct FourBarState {
  double cyl = 0.0, rod = 0.0;        ///< rad, m
  double dcyl = 0.0, drod = 0.0;      ///< d/dq2
  double ddcyl = 0.0, ddrod = 0.0;    ///< d^2/dq2^2
};

class FourBar {
 public:
  /// Reads the geometry from the compiled model. Throws std::invalid_argument if the linkage is
  /// not planar about y, the rod end is off the slide axis, or the loop is not assembled at
  /// qpos = 0 (|r(0) - p| > 1e-9 m).
  FourBar(const mjModel* m, const LegIndices& idx);
  FourBarState closure(double q2) const;

 private:
  double cx_, cz_, kx_, kz_, dx_, dz_;  // C, K (thigh frame), D (shank frame)
  double p_len_, p_psi_;
};

/// Sets hip/knee positions and velocities, and the passive joints by the closure
/// (positions and velocities; accelerations too when qdd != nullptr, into d->qacc).
void setLegState(const mjModel* m, mjData* d, const LegIndices& idx, const FourBar& fb,
                 const std::array<double, 2>& q, const std::array<double, 2>& qd,
                 const std::array<double, 2>* qdd = nullptr);

/// Distance (m) between the loop connect's two anchors, from d->xpos/xmat (valid after the
/// kinematics of the current state). 0 if the model has no loop.
double loopError(const mjModel* m, const mjData* d, const LegIndices& idx);

}  // namespace exoid::sim
