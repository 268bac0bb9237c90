// A URDF's chain as the MJCF the chain rig simulates (sim/chain_mjcf.hpp): read back from the
// compiled model, every body, joint frame, limit and friction is the URDF's, on a fixed base and
// on the stand; a massless link is refused naming it.
#include "exoid/sim/chain_mjcf.hpp"
#include "exoid/sim/model.hpp"
#include "exoid/sim/serial_chain.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace exoid::sim {
namespace {

TEST(ChainMjcf, TheCompiledModelIsTheUrdfsChain) {
  const SerialChain urdf = serialChainFromUrdf(std::string(EXOID_SOURCE_DIR) + "/models/leg3.urdf");
  std::vector<double> coulomb;
  for (const ChainLinkBody& l : urdf.links) coulomb.push_back(l.coulomb_Nm);
  for (const bool mount : {false, true}) {
    const ModelPtr m = compileMjcf(chainMjcf(urdf, mount), "leg3.urdf as MJCF");
    const SerialChain back = serialChainFromMjcf(m.get(), drivenHinges(m.get(), "leg3.urdf as MJCF"), coulomb, "leg3.urdf as MJCF");
    ASSERT_EQ(back.jointNames(), urdf.jointNames());
    // MuJoCo stores each inertia in its principal axes: back in the link frame to rounding.
    const double tol = 1e-12;
    EXPECT_LE((back.gravity_mps2 - urdf.gravity_mps2).norm(), tol);
    for (std::size_t k = 0; k < urdf.links.size(); ++k) {
      const ChainLinkBody &a = urdf.links[k], &b = back.links[k];
      EXPECT_NEAR(b.mass_kg, a.mass_kg, tol * a.mass_kg) << a.link << " mount " << mount;
      EXPECT_LE((b.com_m - a.com_m).norm(), tol) << a.link;
      EXPECT_LE((b.inertia_com_kgm2 - a.inertia_com_kgm2).norm(), tol * a.inertia_com_kgm2.norm()) << a.link;
      EXPECT_LE((b.parent_p_joint_m - a.parent_p_joint_m).norm(), tol) << a.link;
      EXPECT_LE((b.parent_R_joint - a.parent_R_joint).norm(), tol) << a.link;
      EXPECT_LE((b.axis - a.axis).norm(), tol) << a.link;
      EXPECT_EQ(b.damping_Nms, a.damping_Nms) << a.link;
      EXPECT_EQ(b.coulomb_Nm, a.coulomb_Nm) << a.link;
      EXPECT_EQ(b.q_min_rad, a.q_min_rad) << a.link;
      EXPECT_EQ(b.q_max_rad, a.q_max_rad) << a.link;
      EXPECT_EQ(b.tau_max_Nm, a.tau_max_Nm) << a.link;
    }
    // The stand's three mount joints and nothing else besides the chain.
    EXPECT_EQ(m->njnt, static_cast<int>(urdf.links.size()) + (mount ? 3 : 0));
  }
  SerialChain massless = urdf;
  massless.links[1].mass_kg = 0.0;
  try {
    chainMjcf(massless, false);
    FAIL() << "a massless link was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'" + urdf.links[1].link + "'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace exoid::sim
