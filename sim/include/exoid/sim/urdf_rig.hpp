#pragma once
// A serial chain read from a URDF as an MJCF the chain rig simulates: a URDF has no motors, no
// armature and no stand, so each joint gets a motor (its effort as the force range), its viscous
// friction as joint damping and its Coulomb friction as exoid_fc_<joint>; with a mount, the chain
// stands on a stand like models/leg3.xml's (its 40 kg on the same mount joints of class "mount":
// vibration_level, and a 20 kg base), the mount pivoting at the chain's base frame.
#include "exoid/sim/serial_chain.hpp"

#include <string>

namespace exoid::sim {

/// MJCF text of `chain` (its bodies as read: mass, COM, inertia about the COM, joint frames), the
/// base fixed to the world or, with_mount, on the stand. Throws std::invalid_argument naming the
/// chain's source and link when MuJoCo could not simulate a link (no mass; an inertia with a
/// moment not positive or above the sum of the other two: a point mass, a rod), and naming a
/// link or joint that takes a name the rig uses (world, exoid_stand, exoid_base, mount_*).
/// with_shapes: each link drawn (a URDF's meshes are not read) as a capsule from its joint to the
/// next one (the tip's: to twice its COM) and a sphere at its COM; they collide with nothing and
/// carry no mass (every body's inertial is given), so the dynamics are the same.
std::string urdfRigMjcf(const SerialChain& chain, bool with_mount, bool with_shapes = false);

/// The rig of the chain `selection` picks out of the URDF at `path`: urdfRigMjcf compiled, errors
/// naming the file. The simulator's model, and render's (with_shapes).
ModelPtr compileUrdfRig(const std::string& path, const ChainSelection& selection, bool with_mount, bool with_shapes = false);

}  // namespace exoid::sim
