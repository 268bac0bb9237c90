#pragma once
// The pedestal IMU's true readings, from the mount's generalized state (after mj_forward).
//
// The mount is two world-axis slides (x, z) and then a pitch hinge (axis y) at the pedestal's
// origin O, so the IMU point P at r = P - O moves with
//   a_P = (x'', 0, z'') + th'' (y x r) - th'^2 r_perp,     r_perp = (r_x, 0, r_z),
// and an accelerometer reads the specific force in its own (pedestal-rotated) frame,
// f = R_y(th)^T (a_P - g), i.e. +9.81 m/s^2 on z at rest; the gyro reads th' about y.
// A welded pedestal reads gravity alone.
#include "exoid/sim/model.hpp"

#include <Eigen/Core>

namespace exoid::sim {

/// [acc_x, acc_z, gyro_y] (m/s^2, m/s^2, rad/s) in the IMU frame, noise-free.
Eigen::Vector3d pedestalImuTruth(const mjModel* m, const mjData* d, const LegIndices& x);

}  // namespace exoid::sim
