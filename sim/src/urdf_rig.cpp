#include "exoid/sim/urdf_rig.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace exoid::sim {

namespace {

// Round-trip digits, whatever the process's locale (a host may set a comma decimal point).
std::string num(double v) {
  char buf[32];
  const std::to_chars_result r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 17);
  return std::string(buf, r.ptr);
}

// A name as an XML attribute value.
std::string xmlName(const std::string& name) {
  std::string out;
  for (const char c : name) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

// What MuJoCo needs of a moving body, checked here to name the URDF's link, not a line of the
// generated text: a positive mass and a positive definite inertia satisfying the triangle
// inequality of principal moments (a point mass, a rod or a plate does not).
void checkSimulable(const SerialChain& chain, const ChainLinkBody& l) {
  const std::string where = "'" + chain.source + "': link '" + l.link + "' (joint '" + l.joint + "') ";
  if (!(l.mass_kg > 0.0)) throw std::invalid_argument(where + "has no mass: MuJoCo simulates no massless moving body");
  const Eigen::Vector3d I = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(l.inertia_com_kgm2).eigenvalues();  // ascending
  if (!(I[0] > 0.0) || I[2] > (I[0] + I[1]) * (1.0 + 1e-12)) {  // a plate's sum, to rounding, is allowed
    throw std::invalid_argument(where + "has principal moments of inertia " + num(I[0]) + ", " + num(I[1]) + ", " + num(I[2]) +
                                " kg m^2 about its COM: MuJoCo simulates a body only with every moment positive and none above the sum "
                                "of the other two (identification takes it as it is)");
  }
}

void checkNames(const SerialChain& chain) {
  for (const ChainLinkBody& l : chain.links) {
    for (const std::string& name : {l.link, l.joint}) {
      for (const char* reserved : {"world", "exoid_stand", "exoid_base", "mount_x", "mount_z", "mount_pitch"}) {
        if (name == reserved) {
          throw std::invalid_argument("'" + chain.source + "': '" + name + "' is a name the simulated rig uses itself; rename the link or joint");
        }
      }
    }
  }
}

std::string vec(const Eigen::Vector3d& v) { return num(v.x()) + " " + num(v.y()) + " " + num(v.z()); }

// What renders a link: a capsule from its joint to the next joint (the tip's to twice its COM), a
// sphere at its COM; both sized to the chain's reach, visual only.
void writeShapes(std::ostream& x, const SerialChain& chain, std::size_t k, double radius_m, const std::string& pad) {
  const ChainLinkBody& l = chain.links[k];
  const Eigen::Vector3d end = k + 1 < chain.links.size() ? chain.links[k + 1].parent_p_joint_m : Eigen::Vector3d(2.0 * l.com_m);
  const char* visual = "contype=\"0\" conaffinity=\"0\" mass=\"0\"";
  if (end.norm() > 1e-9) {
    x << pad << "  <geom type=\"capsule\" fromto=\"0 0 0 " << vec(end) << "\" size=\"" << num(radius_m) << "\" " << visual
      << " rgba=\"0.45 0.55 0.7 1\"/>\n";
  }
  x << pad << "  <geom type=\"sphere\" pos=\"" << vec(l.com_m) << "\" size=\"" << num(1.6 * radius_m) << "\" " << visual
    << " rgba=\"0.85 0.5 0.2 1\"/>\n";
}

// The bodies base to tip, each nested in the one before.
void writeLinks(std::ostream& x, const SerialChain& chain, const std::string& indent, bool with_shapes) {
  double reach_m = 0.0;
  for (std::size_t k = 1; k < chain.links.size(); ++k) reach_m += chain.links[k].parent_p_joint_m.norm();
  if (!chain.links.empty()) reach_m += 2.0 * chain.links.back().com_m.norm();
  const double radius_m = 0.025 * std::max(reach_m, 0.2);
  std::string pad = indent;
  for (std::size_t k = 0; k < chain.links.size(); ++k) {
    const ChainLinkBody& l = chain.links[k];
    checkSimulable(chain, l);
    const Eigen::Quaterniond q(l.parent_R_joint);
    x << pad << "<body name=\"" << xmlName(l.link) << "\" pos=\"" << vec(l.parent_p_joint_m) << "\" quat=\"" << num(q.w()) << " " << num(q.x()) << " "
      << num(q.y()) << " " << num(q.z()) << "\">\n";
    x << pad << "  <joint name=\"" << xmlName(l.joint) << "\" type=\"hinge\" axis=\"" << vec(l.axis) << "\" damping=\"" << num(l.damping_Nms)
      << "\" armature=\"" << num(l.armature_kgm2) << "\"";
    if (std::isfinite(l.q_min_rad) && std::isfinite(l.q_max_rad)) x << " range=\"" << num(l.q_min_rad) << " " << num(l.q_max_rad) << "\"";
    x << "/>\n";
    const Eigen::Matrix3d& I = l.inertia_com_kgm2;
    x << pad << "  <inertial pos=\"" << vec(l.com_m) << "\" mass=\"" << num(l.mass_kg) << "\" fullinertia=\"" << num(I(0, 0)) << " "
      << num(I(1, 1)) << " " << num(I(2, 2)) << " " << num(I(0, 1)) << " " << num(I(0, 2)) << " " << num(I(1, 2)) << "\"/>\n";
    if (with_shapes) writeShapes(x, chain, k, radius_m, pad);
    pad += "  ";
  }
  for (std::size_t k = chain.links.size(); k > 0; --k) {
    pad.resize(pad.size() - 2);
    x << pad << "</body>\n";
  }
}

}  // namespace

std::string urdfRigMjcf(const SerialChain& chain, bool with_mount, bool with_shapes) {
  checkNames(chain);
  std::ostringstream x;
  x << "<mujoco model=\"" << xmlName(chain.name) << "\">\n"
    << "  <compiler autolimits=\"true\" angle=\"radian\"/>\n"
    << "  <option timestep=\"0.001\" integrator=\"RK4\" gravity=\"" << vec(chain.gravity_mps2) << "\">\n"
    << "    <flag contact=\"disable\"/>\n  </option>\n  <custom>\n";
  for (const ChainLinkBody& l : chain.links) x << "    <numeric name=\"exoid_fc_" << xmlName(l.joint) << "\" data=\"" << num(l.coulomb_Nm) << "\"/>\n";
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
    writeLinks(x, chain, "        ", with_shapes);
    x << "      </body>\n    </body>\n";
  } else {
    writeLinks(x, chain, "    ", with_shapes);
  }
  x << "  </worldbody>\n  <actuator>\n";
  for (const ChainLinkBody& l : chain.links) {
    x << "    <motor name=\"" << xmlName(l.joint) << "_motor\" joint=\"" << xmlName(l.joint) << "\" gear=\"1\"";
    if (std::isfinite(l.tau_max_Nm)) x << " forcerange=\"" << num(-l.tau_max_Nm) << " " << num(l.tau_max_Nm) << "\"";
    x << "/>\n";
  }
  x << "  </actuator>\n</mujoco>\n";
  return x.str();
}

ModelPtr compileUrdfRig(const std::string& path, const ChainSelection& selection, bool with_mount, bool with_shapes) {
  return compileMjcf(urdfRigMjcf(serialChainFromUrdf(path, selection), with_mount, with_shapes), "'" + path + "' (as MJCF)");
}

}  // namespace exoid::sim
