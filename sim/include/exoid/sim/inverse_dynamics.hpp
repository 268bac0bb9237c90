#pragma once
// Joint torques of the ideal rig: the welded model, the four-bar treated as a rigid closed
// loop. mj_inverse runs with the loop equality and the hip lock disabled and the passive joints
// set by the analytic closure (positions, velocities, accelerations); the passive joints' forces
// are then mapped onto the knee by virtual work:
//   tau_hip  = qfrc_inverse[hip] + fc1 tanh(qd1/v0)
//   tau_knee = qfrc_inverse[knee] + dcyl/dq2 qfrc_inverse[cyl] + drod/dq2 qfrc_inverse[rod]
//              + fc2 tanh(qd2/v0)
// (the passive coordinates depend on q2 only). This is the motor torque a vibration-free rig
// needs for the given joint motion; continuous-time dynamics (docs/mujoco.md note 5).
#include "exoid/sim/four_bar.hpp"
#include "exoid/sim/model.hpp"

#include <Eigen/Core>

namespace exoid::sim {

class IdealInverseDynamics {
 public:
  /// Takes a loaded leg (welded or not: mount dofs are held at 0). Throws std::invalid_argument
  /// on a model without the loop's elements.
  explicit IdealInverseDynamics(LegModel leg);
  /// Motor torques (N m) for joint positions, velocities, accelerations. Allocation-free.
  Eigen::Vector2d torque(const Eigen::Vector2d& q, const Eigen::Vector2d& qd,
                         const Eigen::Vector2d& qdd);
  const LegModel& leg() const { return leg_; }

 private:
  LegModel leg_;
  DataPtr data_;
  FourBar fb_;
  bool passive_massless_;
};

}  // namespace exoid::sim
