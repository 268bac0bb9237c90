// X of the rigid links of a URDF (urdfdom). The URDF cannot hold the four-bar loop, so it
// carries the bare links only (no cylinder, no rod).
#include "exoid/sim/truth.hpp"

#include "urdf_file.hpp"

#include <Eigen/Geometry>
#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <stdexcept>

namespace exoid::sim {
namespace {

Eigen::Matrix3d rot(const urdf::Rotation& r) {
  return Eigen::Quaterniond(r.w, r.x, r.y, r.z).normalized().toRotationMatrix();
}
Eigen::Vector3d vec(const urdf::Vector3& v) { return {v.x, v.y, v.z}; }

struct LinkSums {
  double mass = 0, Mx = 0, My = 0, J = 0;
};

// Adds `link` (pose R, p in the joint frame) and the links fixed below it.
void addLink(const std::string& path, const urdf::ModelInterface& model, const urdf::Link& link, const Eigen::Matrix3d& R,
             const Eigen::Vector3d& p, LinkSums& s) {
  checkUsedLink(path, model, link);
  if (link.inertial) {
    const urdf::Inertial& in = *link.inertial;
    Eigen::Matrix3d I;
    I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
    const Eigen::Matrix3d Ri = R * rot(in.origin.rotation);
    const Eigen::Matrix3d Il = Ri * I * Ri.transpose();
    const Eigen::Vector3d c = p + R * vec(in.origin.position);
    s.mass += in.mass;
    s.Mx += in.mass * (-c.z());
    s.My += in.mass * (-c.x());
    s.J += Il(1, 1) + in.mass * (c.x() * c.x() + c.z() * c.z());
  }
  for (const auto& j : link.child_joints) {
    if (j->type != urdf::Joint::FIXED) continue;
    const auto child = model.getLink(j->child_link_name);
    if (!child) continue;
    const urdf::Pose& o = j->parent_to_joint_origin_transform;
    addLink(path, model, *child, R * rot(o.rotation), p + R * vec(o.position), s);
  }
}

}  // namespace

Truth truthFromUrdf(const std::string& path) {
  const urdf::ModelInterfaceSharedPtr model = readUrdf(path);
  urdf::JointConstSharedPtr joints[2] = {model->getJoint("hip"), model->getJoint("knee")};
  const char* names[2] = {"hip", "knee"};
  for (int k = 0; k < 2; ++k) {
    const auto& j = joints[k];
    if (!j) throw std::invalid_argument("'" + path + "': no joint named '" + names[k] + "'");
    if (j->type != urdf::Joint::REVOLUTE && j->type != urdf::Joint::CONTINUOUS) {
      throw std::invalid_argument("'" + path + "': joint '" + names[k] + "' must be revolute or continuous");
    }
    if (std::abs(j->axis.x) > 1e-12 || std::abs(j->axis.y - 1) > 1e-12 || std::abs(j->axis.z) > 1e-12) {
      throw std::invalid_argument("'" + path + "': joint '" + names[k] + "' axis must be 0 1 0");
    }
    const urdf::Rotation& r = j->parent_to_joint_origin_transform.rotation;
    if (std::abs(r.w) < 1 - 1e-12) {
      throw std::invalid_argument("'" + path + "': joint '" + names[k] + "' origin must not be rotated (rpy 0 0 0)");
    }
  }
  const auto thigh = model->getLink(joints[0]->child_link_name);
  const auto shank = model->getLink(joints[1]->child_link_name);
  if (!thigh || !shank || joints[1]->parent_link_name != joints[0]->child_link_name) {
    throw std::invalid_argument("'" + path + "': expected hip -> thigh link -> knee -> shank link");
  }
  const urdf::Vector3& kp = joints[1]->parent_to_joint_origin_transform.position;
  if (std::abs(kp.x) > 1e-12 || !(kp.z < 0)) {
    throw std::invalid_argument("'" + path + "': the knee joint origin must be (0, y, -Lt) in the thigh frame");
  }
  const double Lt = -kp.z;
  LinkSums t, s;
  // Thigh alone (the knee joint is not fixed, so the shank is not included).
  addLink(path, *model, *thigh, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), t);
  addLink(path, *model, *shank, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), s);
  Truth tr;
  tr.x[5] = s.Mx;
  tr.x[6] = s.My;
  tr.x[7] = s.J;
  tr.x[0] = t.Mx + s.mass * Lt;
  tr.x[1] = t.My;
  tr.x[2] = t.J + s.mass * Lt * Lt + s.J;
  tr.x[3] = joints[0]->dynamics ? joints[0]->dynamics->friction : 0.0;
  tr.x[4] = joints[0]->dynamics ? joints[0]->dynamics->damping : 0.0;
  tr.x[8] = joints[1]->dynamics ? joints[1]->dynamics->friction : 0.0;
  tr.x[9] = joints[1]->dynamics ? joints[1]->dynamics->damping : 0.0;
  tr.thigh_length_m = Lt;
  tr.gravity_mps2 = 9.81;
  tr.thigh_mass_kg = t.mass;
  tr.shank_mass_kg = s.mass;
  tr.source = path;
  return tr;
}

UrdfJointLimits urdfJointLimits(const std::string& path) {
  const urdf::ModelInterfaceSharedPtr model = readUrdf(path);
  UrdfJointLimits out;
  const char* names[2] = {"hip", "knee"};
  for (std::size_t k = 0; k < 2; ++k) {
    const urdf::JointConstSharedPtr j = model->getJoint(names[k]);
    if (!j) throw std::invalid_argument("'" + path + "': no joint named '" + names[k] + "'");
    if (!j->limits || !(j->limits->upper > j->limits->lower) || !(j->limits->effort > 0) || !(j->limits->velocity > 0)) {
      throw std::invalid_argument("'" + path + "': joint '" + names[k] +
                                  "' needs <limit lower upper effort velocity> with upper > lower and positive effort and velocity");
    }
    out.lower_rad[k] = j->limits->lower;
    out.upper_rad[k] = j->limits->upper;
    out.effort_Nm[k] = j->limits->effort;
    out.velocity_radps[k] = j->limits->velocity;
  }
  return out;
}

}  // namespace exoid::sim
