#pragma once
// MuJoCo's error and warning hooks turned into C++ errors (docs/mujoco.md note 8): no
// MUJOCO_LOG.TXT, no exit(1), no silent reset after a bad acceleration.
#include <mujoco/mujoco.h>

#include <cstddef>
#include <stdexcept>
#include <string>

namespace exoid::sim {

/// A MuJoCo error (mju_error) or a model that does not compile; what() carries MuJoCo's message.
class MujocoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The simulation became invalid (MuJoCo warning, non-finite state, open loop): the run stops.
class SimulationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Installs the hooks once per process (thread-safe, idempotent): errors throw MujocoError,
/// warnings are counted and their text kept. Every loader in this library calls it.
void installMujocoHooks();

/// Number of MuJoCo warnings reported through the hook since the process started.
std::size_t mujocoWarningCount();
/// Text of the last warning ("" if none).
std::string lastMujocoWarning();

/// Name of a mjtWarning value, e.g. "mjWARN_BADQACC".
const char* warningName(int warning);

/// Throws SimulationError if `d` has any MuJoCo warning recorded (d->warning[i].number > 0) or
/// a non-finite qpos/qvel/qacc. `t_s` and `context` go into the message. Allocation-free when
/// all is well.
void checkStepHealth(const mjModel* m, const mjData* d, double t_s, const char* context);

}  // namespace exoid::sim
