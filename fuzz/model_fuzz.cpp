// The robot model readers (a URDF through urdfdom, an MJCF through MuJoCo) and the chain taken out
// of them (base, tip, locks), on arbitrary bytes: either std::invalid_argument or MuJoCo's error
// naming the problem, or a chain whose links are physical (finite, mass >= 0, symmetric inertia,
// unit axes, rotations) in a finite gravity.
#include "fuzz_support.hpp"

#include "exoid/sim/mujoco_hooks.hpp"
#include "exoid/sim/serial_chain.hpp"

#include <cmath>
#include <stdexcept>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace exoid::sim;
  if (size < 1) return 0;
  // Bit 0 names the file .xml or .urdf (its root element picks the reader; the name only when it
  // has none); bits 1-2 a selection the corpus's trees have.
  const bool mjcf = data[0] & 1;
  ChainSelection selection;
  switch ((data[0] >> 1) & 3) {
    case 1: selection = {"pelvis", "l_sole", {}}; break;
    case 2: selection = {"", mjcf ? "l_fore" : "foot", {}}; break;
    case 3: selection = {mjcf ? "torso" : "pelvis", mjcf ? "l_fore" : "l_forearm", {{mjcf ? "l_wr" : "head_yaw", 0.3}, {"r_shoulder", 0.5}, {"r_elbow", 1.0}}}; break;
    default: break;
  }
  const std::string path = exoid::fuzz::asFile(data + 1, size - 1, mjcf ? ".xml" : ".urdf");
  SerialChain chain;
  try {
    chain = serialChainFromFile(path, selection);
  } catch (const std::invalid_argument&) {
    return 0;
  } catch (const MujocoError&) {
    return 0;
  }
  EXOID_FUZZ_CHECK(!chain.links.empty() && chain.gravity_mps2.allFinite());
  for (const ChainLinkBody& l : chain.links) {
    EXOID_FUZZ_CHECK(std::isfinite(l.mass_kg) && l.mass_kg >= 0.0);
    EXOID_FUZZ_CHECK(l.com_m.allFinite() && l.inertia_com_kgm2.allFinite() && l.parent_p_joint_m.allFinite());
    const double scale = std::max(1.0, l.inertia_com_kgm2.cwiseAbs().maxCoeff());
    EXOID_FUZZ_CHECK((l.inertia_com_kgm2 - l.inertia_com_kgm2.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * scale);
    EXOID_FUZZ_CHECK(std::abs(l.axis.norm() - 1.0) <= 1e-9);
    EXOID_FUZZ_CHECK((l.parent_R_joint.transpose() * l.parent_R_joint - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-9);
  }
  return 0;
}
