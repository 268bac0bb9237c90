// A URDF's revolute joints as a serial chain (urdfdom): links fixed below a moving link are
// lumped into it; anything that is not a serial chain of revolute joints is refused by name.
#include "exoid/sim/serial_chain.hpp"

#include <Eigen/Geometry>
#include <urdf_parser/urdf_parser.h>

#include <fstream>
#include <stdexcept>

namespace exoid::sim {
namespace {

Eigen::Matrix3d rotationOf(const urdf::Rotation& r) { return Eigen::Quaterniond(r.w, r.x, r.y, r.z).normalized().toRotationMatrix(); }
Eigen::Vector3d vectorOf(const urdf::Vector3& v) { return {v.x, v.y, v.z}; }

const char* typeName(int type) {
  switch (type) {
    case urdf::Joint::REVOLUTE: return "revolute";
    case urdf::Joint::CONTINUOUS: return "continuous";
    case urdf::Joint::PRISMATIC: return "prismatic";
    case urdf::Joint::FLOATING: return "floating";
    case urdf::Joint::PLANAR: return "planar";
    case urdf::Joint::FIXED: return "fixed";
    default: return "unknown";
  }
}

bool moves(const urdf::Joint& j) { return j.type != urdf::Joint::FIXED; }

// Mass, first moment and inertia about the origin of `link` and the links fixed below it, in the
// frame where `link` sits at (R, p).
struct Lump {
  double mass = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia_origin = Eigen::Matrix3d::Zero();
};

// The moving joints below `link` through fixed joints: the chain's next joint, if any.
void collect(const urdf::ModelInterface& model, const urdf::Link& link, const Eigen::Matrix3d& R, const Eigen::Vector3d& p,
             Lump& lump, std::vector<std::pair<urdf::JointConstSharedPtr, Eigen::Isometry3d>>& next) {
  if (link.inertial) {
    const urdf::Inertial& in = *link.inertial;
    Eigen::Matrix3d I;
    I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
    const Eigen::Matrix3d Ri = R * rotationOf(in.origin.rotation);
    const Eigen::Vector3d c = p + R * vectorOf(in.origin.position);
    lump.mass += in.mass;
    lump.first += in.mass * c;
    lump.inertia_origin += Ri * I * Ri.transpose() + in.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  }
  for (const auto& j : link.child_joints) {
    const urdf::Pose& o = j->parent_to_joint_origin_transform;
    const Eigen::Matrix3d Rj = R * rotationOf(o.rotation);
    const Eigen::Vector3d pj = p + R * vectorOf(o.position);
    if (moves(*j)) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.linear() = Rj;
      T.translation() = pj;
      next.emplace_back(j, T);
      continue;
    }
    if (const auto child = model.getLink(j->child_link_name)) collect(model, *child, Rj, pj, lump, next);
  }
}

}  // namespace

SerialChain serialChainFromUrdf(const std::string& path) {
  {
    std::ifstream probe(path);
    if (!probe) throw std::invalid_argument("cannot read URDF file '" + path + "'");
  }
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(path);
  if (!model) throw std::invalid_argument("'" + path + "': urdfdom could not parse the URDF (see its message above)");
  for (const auto& [name, joint] : model->joints_) {
    if (joint->type == urdf::Joint::PRISMATIC || joint->type == urdf::Joint::FLOATING || joint->type == urdf::Joint::PLANAR) {
      throw std::invalid_argument("'" + path + "': joint '" + name + "' is " + typeName(joint->type) +
                                  ": exoid identifies serial chains of revolute joints only (a floating base is not taken either)");
    }
  }
  SerialChain chain;
  chain.name = model->getName();
  chain.source = path;
  chain.gravity_mps2 = Eigen::Vector3d(0.0, 0.0, -9.81);
  // From the root: the base and its fixed links, then link by link.
  std::vector<std::pair<urdf::JointConstSharedPtr, Eigen::Isometry3d>> next;
  Lump base;
  collect(*model, *model->getRoot(), Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), base, next);
  while (!next.empty()) {
    if (next.size() > 1) {
      throw std::invalid_argument("'" + path + "': joints '" + next[0].first->name + "' and '" + next[1].first->name +
                                  "' both move links below the same link: a tree, not a serial chain (exoid takes one "
                                  "chain; make the other joints fixed)");
    }
    const urdf::Joint& j = *next[0].first;
    const Eigen::Isometry3d T = next[0].second;
    ChainLinkBody link;
    link.joint = j.name;
    link.link = j.child_link_name;
    link.parent_R_joint = T.linear();
    link.parent_p_joint_m = T.translation();
    link.axis = vectorOf(j.axis).normalized();
    if (j.dynamics) {
      link.coulomb_Nm = j.dynamics->friction;
      link.damping_Nms = j.dynamics->damping;
    }
    if (j.limits) {
      if (j.type == urdf::Joint::REVOLUTE) {
        link.q_min_rad = j.limits->lower;
        link.q_max_rad = j.limits->upper;
      }
      if (j.limits->velocity > 0.0) link.qd_max_radps = j.limits->velocity;
      if (j.limits->effort > 0.0) link.tau_max_Nm = j.limits->effort;
    }
    std::vector<std::pair<urdf::JointConstSharedPtr, Eigen::Isometry3d>> below;
    Lump lump;
    const auto child = model->getLink(j.child_link_name);
    if (!child) throw std::invalid_argument("'" + path + "': joint '" + j.name + "' names a missing link '" + j.child_link_name + "'");
    collect(*model, *child, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), lump, below);
    link.mass_kg = lump.mass;
    link.com_m = lump.mass > 0.0 ? Eigen::Vector3d(lump.first / lump.mass) : Eigen::Vector3d::Zero();
    const Eigen::Vector3d& c = link.com_m;
    link.inertia_com_kgm2 = lump.inertia_origin - lump.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
    chain.links.push_back(link);
    next = below;
  }
  if (chain.links.empty()) throw std::invalid_argument("'" + path + "': no revolute or continuous joint: no chain to identify");
  return chain;
}

}  // namespace exoid::sim
