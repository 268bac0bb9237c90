// A URDF's chain as the MJCF the chain rig simulates (sim/urdf_rig.hpp): read back from the
// compiled model, every body, joint frame, limit and friction is the URDF's, on a fixed base and
// on the stand; what MuJoCo cannot simulate or name is refused naming the link.
#include "exoid/sim/urdf_rig.hpp"
#include "exoid/sim/model.hpp"
#include "exoid/sim/serial_chain.hpp"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace exoid::sim {
namespace {

// leg3's chain, or the same with a rotated knee frame, a skew knee axis and a full inertia, names
// XML must escape and no Coulomb friction on the ankle: what a URDF may hold that leg3's does not.
SerialChain leg3(bool general) {
  SerialChain c = serialChainFromUrdf(std::string(EXOID_SOURCE_DIR) + "/models/leg3.urdf");
  if (!general) return c;
  ChainLinkBody& knee = c.links[1];
  knee.parent_R_joint = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 0.1, 1.0).normalized()).toRotationMatrix();
  knee.axis = Eigen::Vector3d(0.3, 0.9, 0.1).normalized();
  knee.inertia_com_kgm2 << 0.06, 0.004, -0.002, 0.004, 0.05, 0.003, -0.002, 0.003, 0.02;
  knee.link = "shank <&\"'>";
  knee.joint = "knee&1";
  c.links[2].coulomb_Nm = 0.0;
  return c;
}

void expectTheSameChain(const SerialChain& urdf, bool mount, bool shapes) {
  const ModelPtr m = compileMjcf(urdfRigMjcf(urdf, mount, shapes), "the chain as MJCF");
  std::vector<double> coulomb;
  for (const ChainLinkBody& l : urdf.links) coulomb.push_back(l.coulomb_Nm);
  const SerialChain back = serialChainFromMjcf(m.get(), drivenHinges(m.get(), "the chain as MJCF"), coulomb, "the chain as MJCF");
  ASSERT_EQ(back.jointNames(), urdf.jointNames());
  // Frames, masses and positions come back to rounding. MuJoCo stores each inertia in its
  // principal axes: a diagonal one comes back to rounding too, a full one through its compiler's
  // iterative eigen decomposition, measured 3.4e-7 relative on this knee (the sidecar's truth is
  // read back from the compiled model, so a fit is judged against what was simulated).
  const double tol = 1e-12, inertia_tol = 1e-6;
  EXPECT_LE((back.gravity_mps2 - urdf.gravity_mps2).norm(), tol);
  for (std::size_t k = 0; k < urdf.links.size(); ++k) {
    const ChainLinkBody &a = urdf.links[k], &b = back.links[k];
    EXPECT_EQ(b.link, a.link);
    EXPECT_NEAR(b.mass_kg, a.mass_kg, tol * a.mass_kg) << a.link;
    EXPECT_LE((b.com_m - a.com_m).norm(), tol) << a.link;
    EXPECT_LE((b.inertia_com_kgm2 - a.inertia_com_kgm2).norm(), inertia_tol * a.inertia_com_kgm2.norm()) << a.link;
    EXPECT_LE((b.parent_p_joint_m - a.parent_p_joint_m).norm(), tol) << a.link;
    EXPECT_LE((b.parent_R_joint - a.parent_R_joint).norm(), tol) << a.link;
    EXPECT_LE((b.axis - a.axis).norm(), tol) << a.link;
    EXPECT_EQ(b.damping_Nms, a.damping_Nms) << a.link;
    EXPECT_EQ(b.q_min_rad, a.q_min_rad) << a.link;
    EXPECT_EQ(b.q_max_rad, a.q_max_rad) << a.link;
    EXPECT_EQ(b.tau_max_Nm, a.tau_max_Nm) << a.link;
    // The Coulomb friction the rig applies, read from the compiled model's numerics.
    const int id = mj_name2id(m.get(), mjOBJ_NUMERIC, ("exoid_fc_" + a.joint).c_str());
    ASSERT_GE(id, 0) << a.joint;
    EXPECT_EQ(m->numeric_data[m->numeric_adr[id]], a.coulomb_Nm) << a.joint;
  }
  // The stand's three mount joints and nothing else besides the chain.
  EXPECT_EQ(m->njnt, static_cast<int>(urdf.links.size()) + (mount ? 3 : 0));
  // Drawn (render's scene), a capsule and a sphere a link, which add no mass (the bodies above).
  EXPECT_EQ(m->ngeom, shapes ? 2 * static_cast<int>(urdf.links.size()) : 0);
  for (int g = 0; g < m->ngeom; ++g) EXPECT_EQ(m->geom_contype[g] | m->geom_conaffinity[g], 0) << g;  // touching nothing
}

TEST(UrdfRig, TheCompiledModelIsTheUrdfsChain) {
  for (const bool general : {false, true}) {
    for (const bool mount : {false, true}) {
      for (const bool shapes : {false, true}) {
        SCOPED_TRACE(std::string(general ? "general" : "leg3") + (mount ? ", on the stand" : ", fixed") + (shapes ? ", drawn" : ""));
        expectTheSameChain(leg3(general), mount, shapes);
      }
    }
  }
}

// No mass, a point mass or a rod (a moment 0), a name the rig uses: refused naming the link.
TEST(UrdfRig, WhatMujocoCannotSimulateIsRefusedNamingTheLink) {
  const SerialChain urdf = leg3(false);
  SerialChain massless = urdf, point = urdf, rod = urdf, reserved = urdf;
  massless.links[2].mass_kg = 0.0;
  point.links[2].inertia_com_kgm2.setZero();
  rod.links[2].inertia_com_kgm2 = Eigen::Vector3d(0.01, 0.01, 0.0).asDiagonal();
  reserved.links[2].link = "exoid_stand";
  for (const SerialChain* bad : {&massless, &point, &rod, &reserved}) {
    try {
      urdfRigMjcf(*bad, true);
      ADD_FAILURE() << "accepted: " << bad->links[2].link;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("'" + bad->links[2].link + "'"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace exoid::sim
