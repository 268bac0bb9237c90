#include "exoid/sim/chain_mjcf.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace exoid::sim {

namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string vec(const Eigen::Vector3d& v) { return num(v.x()) + " " + num(v.y()) + " " + num(v.z()); }

// The bodies base to tip, each nested in the one before.
void writeLinks(std::ostream& x, const SerialChain& chain, const std::string& indent) {
  std::string pad = indent;
  for (const ChainLinkBody& l : chain.links) {
    if (!(l.mass_kg > 0.0)) {
      throw std::invalid_argument("'" + chain.source + "': link '" + l.link + "' (joint '" + l.joint + "') has no mass: MuJoCo simulates "
                                  "no massless moving body");
    }
    const Eigen::Quaterniond q(l.parent_R_joint);
    x << pad << "<body name=\"" << l.link << "\" pos=\"" << vec(l.parent_p_joint_m) << "\" quat=\"" << num(q.w()) << " " << num(q.x()) << " "
      << num(q.y()) << " " << num(q.z()) << "\">\n";
    x << pad << "  <joint name=\"" << l.joint << "\" type=\"hinge\" axis=\"" << vec(l.axis) << "\" damping=\"" << num(l.damping_Nms)
      << "\" armature=\"" << num(l.armature_kgm2) << "\"";
    if (std::isfinite(l.q_min_rad) && std::isfinite(l.q_max_rad)) x << " range=\"" << num(l.q_min_rad) << " " << num(l.q_max_rad) << "\"";
    x << "/>\n";
    const Eigen::Matrix3d& I = l.inertia_com_kgm2;
    x << pad << "  <inertial pos=\"" << vec(l.com_m) << "\" mass=\"" << num(l.mass_kg) << "\" fullinertia=\"" << num(I(0, 0)) << " "
      << num(I(1, 1)) << " " << num(I(2, 2)) << " " << num(I(0, 1)) << " " << num(I(0, 2)) << " " << num(I(1, 2)) << "\"/>\n";
    pad += "  ";
  }
  for (std::size_t k = chain.links.size(); k > 0; --k) {
    pad.resize(pad.size() - 2);
    x << pad << "</body>\n";
  }
}

}  // namespace

std::string chainMjcf(const SerialChain& chain, bool with_mount) {
  std::ostringstream x;
  x << "<mujoco model=\"" << chain.name << "\">\n"
    << "  <compiler autolimits=\"true\" angle=\"radian\"/>\n"
    << "  <option timestep=\"0.001\" integrator=\"RK4\" gravity=\"" << vec(chain.gravity_mps2) << "\">\n"
    << "    <flag contact=\"disable\"/>\n  </option>\n  <custom>\n";
  for (const ChainLinkBody& l : chain.links) x << "    <numeric name=\"exoid_fc_" << l.joint << "\" data=\"" << num(l.coulomb_Nm) << "\"/>\n";
  x << "  </custom>\n  <default>\n    <default class=\"mount\">\n      <joint armature=\"0\"/>\n    </default>\n  </default>\n  <worldbody>\n";
  if (with_mount) {
    // models/leg3.xml's stand at vibration level 1, its mount at the chain's base frame: the base
    // motion its IMU reads is the motion of the frame the URDF's chain is expressed in.
    x << "    <body name=\"exoid_stand\">\n"
      << "      <joint name=\"mount_x\" class=\"mount\" type=\"slide\" axis=\"1 0 0\" stiffness=\"1.2e6\" damping=\"900\"/>\n"
      << "      <joint name=\"mount_z\" class=\"mount\" type=\"slide\" axis=\"0 0 1\" stiffness=\"1.2e6\" damping=\"900\"/>\n"
      << "      <joint name=\"mount_pitch\" class=\"mount\" type=\"hinge\" axis=\"0 1 0\" stiffness=\"1.0e6\" damping=\"1000\"/>\n"
      << "      <inertial pos=\"0.2 0 0.45\" mass=\"40\" diaginertia=\"4.0 4.0 1.5\"/>\n"
      << "      <body name=\"exoid_base\">\n"
      << "        <inertial pos=\"0.05 0 0.2\" mass=\"20\" diaginertia=\"0.6 0.5 0.3\"/>\n";
    writeLinks(x, chain, "        ");
    x << "      </body>\n    </body>\n";
  } else {
    writeLinks(x, chain, "    ");
  }
  x << "  </worldbody>\n  <actuator>\n";
  for (const ChainLinkBody& l : chain.links) {
    x << "    <motor name=\"" << l.joint << "_motor\" joint=\"" << l.joint << "\" gear=\"1\"";
    if (std::isfinite(l.tau_max_Nm)) x << " forcerange=\"" << num(-l.tau_max_Nm) << " " << num(l.tau_max_Nm) << "\"";
    x << "/>\n";
  }
  x << "  </actuator>\n</mujoco>\n";
  return x.str();
}

}  // namespace exoid::sim
