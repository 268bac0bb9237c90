#pragma once
// A serial chain read from a URDF as an MJCF the chain rig simulates: a URDF has no motors, no
// armature and no stand, so each joint gets a motor (its effort as the force range), its viscous
// friction as joint damping and its Coulomb friction as exoid_fc_<joint>; with a mount, the chain
// stands on the compliant stand of models/leg3.xml (joints of class "mount": vibration_level), its
// mount at the chain's base frame.
#include "exoid/sim/serial_chain.hpp"

#include <string>

namespace exoid::sim {

/// MJCF text of `chain` (its bodies as read: mass, COM, inertia about the COM, joint frames), the
/// base fixed to the world or, with_mount, on the stand. Throws std::invalid_argument naming the
/// chain's source and link when a link has no mass (MuJoCo simulates no massless moving body).
std::string chainMjcf(const SerialChain& chain, bool with_mount);

}  // namespace exoid::sim
