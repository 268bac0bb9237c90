#pragma once
// A serial chain of revolute joints: all the generic regressor needs to know of a robot. Built
// outside ident (from a URDF or an MJCF); ident itself reads no robot file.
#include <Eigen/Core>

#include <string>
#include <vector>

namespace exoid::ident {

/// One revolute joint and the link it moves. Frames follow URDF: the joint frame sits in the
/// parent link's frame at (parent_R_joint, parent_p_joint); the child link's frame is the joint
/// frame turned by q about `axis`. The link's inertial parameters are expressed in that frame,
/// about its origin (a point of the joint axis).
struct ChainJoint {
  std::string name;  ///< the joint's name, e.g. "hip": dataset columns q_<name>, tau_<name>
  std::string link;  ///< the child link's name, e.g. "thigh": its parameters are "<link>.m", ...
  Eigen::Matrix3d parent_R_joint = Eigen::Matrix3d::Identity();
  Eigen::Vector3d parent_p_joint_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  ///< unit length, in the joint frame
  bool friction = true;   ///< Coulomb fc sgn(qd) + viscous fv qd act on this joint
  bool armature = false;  ///< Ia qdd on the joint's own diagonal (a reflected rotor inertia)
};

/// Offsets of one joint's parameters in the standard parameter vector: the link's 10, then the
/// joint's fc and fv (if it has friction), then its Ia (if it has armature).
struct JointParameterLayout {
  int link = 0;         ///< first of [m, mx, my, mz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz]
  int friction = -1;    ///< fc, then fv; -1 = none
  int armature = -1;    ///< Ia; -1 = none
};

/// The number of inertial parameters of a rigid body: mass, first moment (3), inertia about the
/// frame origin (6, URDF's order ixx ixy ixz iyy iyz izz).
inline constexpr int kLinkParams = 10;

struct ChainModel {
  std::string name;
  std::vector<ChainJoint> joints;  ///< base to tip; joint i's parent link is link i - 1 (or the base)
  Eigen::Vector3d gravity_mps2{0.0, 0.0, -9.81};  ///< in the base frame

  int dof() const { return static_cast<int>(joints.size()); }
  /// Layout of joint i's parameters (see JointParameterLayout).
  std::vector<JointParameterLayout> layout() const;
  int standardParameterCount() const;
  /// The joints' names, base to tip (a dataset's columns: q_<name>, tau_<name>).
  std::vector<std::string> jointNames() const;
  /// "thigh.m", "thigh.mx", ..., "thigh.Izz", "hip.fc", "hip.fv", "knee.Ia", in layout order.
  std::vector<std::string> standardParameterNames() const;
  /// Throws std::invalid_argument naming the joint: no joints, an empty or repeated name, a
  /// non-unit or non-finite axis, a rotation that is not orthonormal, a non-finite gravity.
  void validate() const;
};

/// The standard parameters of one rigid body (kLinkParams of them, in that order) from its mass,
/// centre of mass and inertia about the centre of mass, all in the link frame (parallel axes).
Eigen::Matrix<double, kLinkParams, 1> linkParameters(double mass_kg, const Eigen::Vector3d& com_m,
                                                    const Eigen::Matrix3d& inertia_com_kgm2);

}  // namespace exoid::ident
