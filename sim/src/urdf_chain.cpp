// A URDF's revolute joints as a serial chain (urdfdom): the chain from a base link to a tip link
// of the tree, each link with the links fixed (or locked) below it lumped in; what is not a
// serial chain of revolute joints is refused by name.
#include "exoid/sim/serial_chain.hpp"

#include "urdf_file.hpp"
#include "exoid/core/format.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <optional>
#include <set>
#include <stdexcept>
#include <utility>

namespace exoid::sim {
namespace {

using JointPtr = urdf::JointConstSharedPtr;
using Step = std::pair<JointPtr, Eigen::Isometry3d>;  // a moving joint and its frame at 0, in the frame collected in

Eigen::Vector3d vectorOf(const urdf::Vector3& v) { return {v.x, v.y, v.z}; }

Eigen::Isometry3d poseOf(const urdf::Pose& o) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(o.rotation.w, o.rotation.x, o.rotation.y, o.rotation.z).normalized().toRotationMatrix();
  T.translation() = vectorOf(o.position);
  return T;
}

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
bool revolute(const urdf::Joint& j) { return j.type == urdf::Joint::REVOLUTE || j.type == urdf::Joint::CONTINUOUS; }

// Mass, first moment and inertia about the origin of a link and what is fixed or locked below it.
struct Lump {
  double mass = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia_origin = Eigen::Matrix3d::Zero();
};

// The file, the selection, and which of its locks the walk has used.
struct Walk {
  const std::string& path;
  const urdf::ModelInterface& model;
  const ChainSelection& selection;
  std::set<std::string> locks_used;

  // The transform across joint j: fixed, or held at its lock.
  Eigen::Isometry3d across(const urdf::Joint& j) {
    Eigen::Isometry3d T = poseOf(j.parent_to_joint_origin_transform);
    const auto lock = selection.locks.find(j.name);
    if (lock == selection.locks.end()) return T;
    locks_used.insert(j.name);
    if (j.type == urdf::Joint::FLOATING || j.type == urdf::Joint::PLANAR) {
      throw std::invalid_argument("'" + path + "': --lock " + j.name + ": a " + typeName(j.type) + " joint cannot be held at one value");
    }
    const Eigen::Vector3d a = vectorOf(j.axis).normalized();
    if (revolute(j)) T.rotate(Eigen::AngleAxisd(lock->second, a));
    if (j.type == urdf::Joint::PRISMATIC) T.translate(lock->second * a);
    return T;
  }

  bool held(const urdf::Joint& j) const { return !moves(j) || selection.locks.count(j.name) > 0; }

  // Adds `link` (at T) and every link fixed or locked below it to `lump` (nullptr: the base, whose
  // mass never moves), and lists the moving joints below them in `next`.
  void collect(const urdf::Link& link, const Eigen::Isometry3d& T, Lump* lump, std::vector<Step>& next) {
    if (lump && link.inertial) {
      checkUsedLink(path, model, link);
      const urdf::Inertial& in = *link.inertial;
      Eigen::Matrix3d I;
      I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
      const Eigen::Isometry3d Ti = T * poseOf(in.origin);
      const Eigen::Matrix3d Ri = Ti.linear();
      const Eigen::Vector3d c = Ti.translation();
      lump->mass += in.mass;
      lump->first += in.mass * c;
      lump->inertia_origin += Ri * I * Ri.transpose() + in.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
    }
    for (const auto& j : link.child_joints) {
      if (!held(*j)) {
        next.emplace_back(j, T * poseOf(j->parent_to_joint_origin_transform));
        continue;
      }
      if (const auto child = model.getLink(j->child_link_name)) collect(*child, T * across(*j), lump, next);
    }
  }
};

// The leaf links below `from` (links with no child joint), in the file's order of the tree.
void leavesBelow(const urdf::Link& from, std::vector<std::string>& out) {
  if (from.child_links.empty()) out.push_back(from.name);
  for (const auto& c : from.child_links) leavesBelow(*c, out);
}

// The links from `base` down to `tip`, both included. Throws when tip is not below base.
std::set<std::string> pathLinks(const std::string& path, const urdf::ModelInterface& model, const std::string& base, const std::string& tip) {
  std::set<std::string> links;
  for (urdf::LinkConstSharedPtr l = model.getLink(tip); l; l = l->getParent()) {
    links.insert(l->name);
    if (l->name == base) return links;
  }
  throw std::invalid_argument("'" + path + "': --tip " + tip + " is not below --base " + base + " (the tree's root is '" + model.getRoot()->name + "')");
}

urdf::LinkConstSharedPtr linkNamed(const std::string& path, const urdf::ModelInterface& model, const std::string& name, const char* option) {
  const urdf::LinkConstSharedPtr l = model.getLink(name);
  if (!l) throw std::invalid_argument("'" + path + "': " + option + " " + name + ": the URDF has no link of that name");
  return l;
}

}  // namespace

SerialChain serialChainFromUrdf(const std::string& path, const ChainSelection& selection) {
  const urdf::ModelInterfaceSharedPtr model = readUrdf(path);
  for (const auto& [joint, value] : selection.locks) {
    if (!model->getJoint(joint)) throw std::invalid_argument("'" + path + "': --lock " + joint + ": the URDF has no joint of that name");
  }
  for (const auto& [joint, value] : selection.locks) {
    if (!std::isfinite(value)) throw std::invalid_argument("'" + path + "': --lock " + joint + ": the value is not a finite number");
  }
  Walk walk{path, *model, selection, {}};
  const urdf::LinkConstSharedPtr base = selection.base.empty() ? model->getRoot() : linkNamed(path, *model, selection.base, "--base");
  std::optional<std::set<std::string>> on_path;
  if (!selection.tip.empty()) on_path = pathLinks(path, *model, base->name, linkNamed(path, *model, selection.tip, "--tip")->name);

  SerialChain chain;
  chain.name = model->getName();
  chain.source = path;
  // Gravity along the root's -z, in the base's frame (the joints above the base held at 0 or their lock).
  Eigen::Matrix3d R_root_base = Eigen::Matrix3d::Identity();
  for (urdf::LinkConstSharedPtr l = base; l->getParent(); l = l->getParent()) R_root_base = walk.across(*l->parent_joint).linear() * R_root_base;
  chain.gravity_mps2 = R_root_base.transpose() * Eigen::Vector3d(0.0, 0.0, -9.81);

  // The next chain joint among the moving joints found below a link: the one towards the tip;
  // below the base the others are left out, below a chain link they are refused.
  const auto pick = [&](const std::vector<Step>& next, const std::string& below) -> std::optional<Step> {
    std::optional<Step> step;
    for (const Step& s : next) {
      const bool towards_tip = on_path ? on_path->count(s.first->child_link_name) > 0 : next.size() == 1;
      if (towards_tip) {
        step = s;
      } else if (chain.links.empty() && on_path) {
        chain.left_out.push_back(s.first->child_link_name);
      } else if (!on_path) {
        std::vector<std::string> leaves;
        leavesBelow(*base, leaves);
        throw std::invalid_argument("'" + path + "': joints '" + next[0].first->name + "' and '" + next[1].first->name +
                                    "' both move links below link '" + below + "': a tree, not a serial chain. Choose the chain with --tip LINK " +
                                    "(and --base LINK, default '" + base->name + "'); the leaf links below '" + base->name + "': " + core::joined(leaves));
      } else {
        throw std::invalid_argument("'" + path + "': joint '" + s.first->name + "' (" + typeName(s.first->type) + ") moves a branch off chain link '" +
                                    below + "': hold it with --lock " + s.first->name + "=VALUE (rad, or m for a prismatic joint; lumped at that posture), or choose " +
                                    "another --base/--tip");
      }
    }
    return step;
  };

  std::vector<Step> next;
  walk.collect(*base, Eigen::Isometry3d::Identity(), nullptr, next);
  for (std::optional<Step> step = pick(next, base->name); step;) {
    const urdf::Joint& j = *step->first;
    if (!revolute(j)) {
      throw std::invalid_argument("'" + path + "': joint '" + j.name + "' is " + typeName(j.type) +
                                  " (on the chain): exoid identifies serial chains of revolute joints only (a floating base is not taken either: "
                                  "choose --base below it" + (j.type == urdf::Joint::PRISMATIC ? std::string(", or hold the joint with --lock") : std::string()) + ")");
    }
    checkChainJoint(path, j);
    ChainLinkBody link;
    link.joint = j.name;
    link.link = j.child_link_name;
    link.parent_R_joint = step->second.linear();
    link.parent_p_joint_m = step->second.translation();
    link.axis = vectorOf(j.axis).normalized();
    if (j.dynamics) {
      link.coulomb_Nm = j.dynamics->friction;
      link.damping_Nms = j.dynamics->damping;
    }
    if (j.limits) {
      if (j.type == urdf::Joint::REVOLUTE && j.limits->lower < j.limits->upper) {  // lower = upper = 0 (URDF's default): not given
        link.q_min_rad = j.limits->lower;
        link.q_max_rad = j.limits->upper;
      }
      if (j.limits->velocity > 0.0) link.qd_max_radps = j.limits->velocity;
      if (j.limits->effort > 0.0) link.tau_max_Nm = j.limits->effort;
    }
    const auto child = model->getLink(j.child_link_name);
    if (!child) throw std::invalid_argument("'" + path + "': joint '" + j.name + "' names a missing link '" + j.child_link_name + "'");
    Lump lump;
    std::vector<Step> below;
    walk.collect(*child, Eigen::Isometry3d::Identity(), &lump, below);
    link.mass_kg = lump.mass;
    link.com_m = lump.mass > 0.0 ? Eigen::Vector3d(lump.first / lump.mass) : Eigen::Vector3d::Zero();
    const Eigen::Vector3d& c = link.com_m;
    link.inertia_com_kgm2 = lump.inertia_origin - lump.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
    chain.links.push_back(link);
    step = pick(below, link.link);
  }
  if (chain.links.empty()) {
    throw std::invalid_argument("'" + path + "': no revolute or continuous joint" + (on_path ? " between --base " + base->name + " and --tip " + selection.tip : std::string()) +
                                ": no chain to identify");
  }
  for (const auto& [joint, value] : selection.locks) {
    if (!walk.locks_used.count(joint)) {
      throw std::invalid_argument("'" + path + "': --lock " + joint + ": the joint is neither on the chain nor on a branch off it or above its base");
    }
  }
  return chain;
}

}  // namespace exoid::sim
