#pragma once
// A robot model read as a serial chain of revolute joints with its rigid bodies: the structure and
// the true physical parameters, in URDF's frame convention (each link's frame on its joint's axis,
// the joint frame placed in the parent link's frame). experiments turns it into ident's
// ChainModel and standard parameter vector; sim itself never includes ident.
#include "exoid/core/tree_selection.hpp"
#include "exoid/sim/model.hpp"

#include <Eigen/Core>

#include <limits>
#include <map>
#include <string>
#include <vector>

namespace exoid::sim {

struct ChainLinkBody {
  std::string joint;  ///< the joint that moves this link, e.g. "hip"
  std::string link;   ///< e.g. "thigh"
  Eigen::Matrix3d parent_R_joint = Eigen::Matrix3d::Identity();
  Eigen::Vector3d parent_p_joint_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  ///< unit, in the link frame
  double mass_kg = 0.0;
  Eigen::Vector3d com_m = Eigen::Vector3d::Zero();                     ///< link frame
  Eigen::Matrix3d inertia_com_kgm2 = Eigen::Matrix3d::Zero();          ///< about the COM, link frame
  double coulomb_Nm = 0.0, damping_Nms = 0.0, armature_kgm2 = 0.0;
  /// The joint's limits, as the file gives them (MJCF: a limited joint's range, a limited motor's
  /// force range times its gear; URDF: <limit lower upper velocity effort>); infinite when absent.
  double q_min_rad = -std::numeric_limits<double>::infinity(), q_max_rad = std::numeric_limits<double>::infinity();
  double qd_max_radps = std::numeric_limits<double>::infinity();
  double tau_max_Nm = std::numeric_limits<double>::infinity();
};

using ChainSelection = core::ChainSelection;

struct SerialChain {
  std::string name, source;
  std::vector<ChainLinkBody> links;  ///< base to tip
  Eigen::Vector3d gravity_mps2{0.0, 0.0, -9.81};  ///< in the base frame (chainBaseBody's at qpos0)
  /// Bodies with their own degrees of freedom hanging off the chain (e.g. the four-bar's
  /// cylinder and rod): left out of every link, named here so that nothing is dropped silently.
  std::vector<std::string> left_out;
  /// The joints that move the links, base to tip.
  std::vector<std::string> jointNames() const {
    std::vector<std::string> names;
    for (const ChainLinkBody& l : links) names.push_back(l.joint);
    return names;
  }
};

/// The body whose frame a chain starting at `first_body` is expressed in: the nearest ancestor
/// with a joint of its own (a stand's mount), else the world: the bodies welded in between (a
/// trunk on its stand) ride with it. A chain's base motion is that body's; its IMU reads it.
int chainBaseBody(const mjModel* m, int first_body);

/// The chain of `joints` (hinge joint ids, base to tip) of a compiled model at qpos0, each link the
/// joint's body and every body welded below it. `coulomb_Nm` per joint (MuJoCo's frictionloss is a
/// soft constraint, not fc sgn(qd): the caller says what its rig applies). Throws
/// std::invalid_argument naming the joint when a joint is not a hinge or is not below the previous one.
/// `locked` (joint id -> qpos) holds those joints there, their bodies lumped into the link above.
SerialChain serialChainFromMjcf(const mjModel* m, const std::vector<int>& joints, const std::vector<double>& coulomb_Nm,
                                const std::string& source, const std::map<int, double>& locked = {});

/// The APAL leg's chain (hip, knee) of a loaded leg, with its Coulomb settings.
SerialChain serialChain(const LegModel& leg);

/// The hinge joints a model's actuators drive, base to tip (joint ids). Throws
/// std::invalid_argument naming `path` when an actuator drives a slide, ball or free joint, or
/// none drives a hinge.
std::vector<int> drivenHinges(const mjModel* m, const std::string& path);
/// The chain of an MJCF file: every hinge driven by a motor (an actuator on a joint), in tree
/// order; Coulomb friction from the custom numerics exoid_fc_<joint> (0 when absent). Throws
/// std::invalid_argument naming the file and what it found: a driven joint that is not a hinge
/// (slide, ball, free), driven joints on two branches (listing the leaf bodies to choose a --tip
/// from), a driven joint off the chain that is not locked, none at all. `selection` names bodies.
SerialChain serialChainFromMjcfFile(const std::string& path, const ChainSelection& selection = {});

/// The chain of a URDF (urdfdom, read strictly: urdf_file.hpp): its revolute and continuous joints
/// from `selection`'s base to its tip, each link with the links fixed (or locked) below it lumped
/// in; Coulomb and viscous friction from <dynamics friction damping>; gravity 9.81 m/s^2 along the
/// root's -z, expressed in the base's frame; no armature (URDF has none). Throws
/// std::invalid_argument naming the file and what it found: a malformed file, a negative mass or an
/// inertia that is not positive semi-definite on a link the chain uses, a non-positive effort or
/// velocity limit on a chain joint, a prismatic, planar or floating joint on the chain, a tree
/// without a tip (listing the leaf links to choose from), a moving branch off a chain link that
/// is not locked, no revolute joint.
SerialChain serialChainFromUrdf(const std::string& path, const ChainSelection& selection = {});

/// By the file's extension: .urdf -> serialChainFromUrdf, else serialChainFromMjcfFile.
SerialChain serialChainFromFile(const std::string& path, const ChainSelection& selection = {});

}  // namespace exoid::sim
