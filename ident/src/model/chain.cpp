#include "exoid/ident/model/chain.hpp"

#include "exoid/core/format.hpp"

#include <Eigen/LU>

#include <cmath>
#include <set>
#include <stdexcept>

namespace exoid::ident {

std::vector<JointParameterLayout> ChainModel::layout() const {
  std::vector<JointParameterLayout> out(joints.size());
  int next = 0;
  for (std::size_t i = 0; i < joints.size(); ++i) {
    out[i].link = next;
    next += kLinkParams;
    if (joints[i].friction) {
      out[i].friction = next;
      next += 2;
    }
    if (joints[i].armature) out[i].armature = next++;
  }
  return out;
}

std::vector<std::string> ChainModel::jointNames() const {
  std::vector<std::string> out;
  for (const ChainJoint& j : joints) out.push_back(j.name);
  return out;
}

int ChainModel::standardParameterCount() const {
  int n = 0;
  for (const ChainJoint& j : joints) n += kLinkParams + (j.friction ? 2 : 0) + (j.armature ? 1 : 0);
  return n;
}

std::vector<std::string> ChainModel::standardParameterNames() const {
  static const char* const kInertial[kLinkParams] = {"m", "mx", "my", "mz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz"};
  std::vector<std::string> names;
  names.reserve(static_cast<std::size_t>(standardParameterCount()));
  for (const ChainJoint& j : joints) {
    for (const char* p : kInertial) names.push_back(j.link + "." + p);
    if (j.friction) {
      names.push_back(j.name + ".fc");
      names.push_back(j.name + ".fv");
    }
    if (j.armature) names.push_back(j.name + ".Ia");
  }
  return names;
}

void ChainModel::validate() const {
  const std::string who = "chain model '" + name + "'";
  if (joints.empty()) throw std::invalid_argument(who + ": no joints (a chain needs at least one revolute joint)");
  if (!gravity_mps2.allFinite()) throw std::invalid_argument(who + ": gravity is not finite");
  std::set<std::string> joint_names, link_names;
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const ChainJoint& j = joints[i];
    const std::string at = who + ", joint " + core::toText(static_cast<int>(i)) + " '" + j.name + "'";
    if (j.name.empty() || j.link.empty()) throw std::invalid_argument(at + ": the joint and its link need names");
    if (!joint_names.insert(j.name).second) throw std::invalid_argument(at + ": a joint of that name comes earlier");
    if (!link_names.insert(j.link).second) throw std::invalid_argument(at + ": link '" + j.link + "' is moved by an earlier joint too");
    if (!j.axis.allFinite() || std::abs(j.axis.norm() - 1.0) > 1e-9) {
      throw std::invalid_argument(at + ": axis must be a unit vector, got norm " + core::formatNumber(j.axis.norm(), 6));
    }
    const double orthonormality = (j.parent_R_joint.transpose() * j.parent_R_joint - Eigen::Matrix3d::Identity()).norm();
    if (!j.parent_R_joint.allFinite() || orthonormality > 1e-9 || j.parent_R_joint.determinant() < 0.0) {
      throw std::invalid_argument(at + ": the joint frame's rotation is not a proper rotation (|R'R - I| = " +
                                  core::formatNumber(orthonormality, 3) + ")");
    }
    if (!j.parent_p_joint_m.allFinite()) throw std::invalid_argument(at + ": the joint frame's origin is not finite");
  }
}

Eigen::Matrix<double, kLinkParams, 1> linkParameters(double mass_kg, const Eigen::Vector3d& com_m,
                                                    const Eigen::Matrix3d& inertia_com_kgm2) {
  // Parallel axes: I_origin = I_com + m (|c|^2 1 - c c').
  const Eigen::Matrix3d I = inertia_com_kgm2 + mass_kg * (com_m.squaredNorm() * Eigen::Matrix3d::Identity() - com_m * com_m.transpose());
  Eigen::Matrix<double, kLinkParams, 1> phi;
  phi << mass_kg, mass_kg * com_m.x(), mass_kg * com_m.y(), mass_kg * com_m.z(), I(0, 0), I(0, 1), I(0, 2), I(1, 1), I(1, 2),
      I(2, 2);
  return phi;
}

}  // namespace exoid::ident
