#pragma once
// The chains the chain tests share: the APAL leg's planar hip-knee chain, random serial chains and
// physically valid parameters for them.
#include "exoid/ident/model/chain.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <string>

namespace exoid::ident::testing {

// The APAL leg as a chain: hip and knee about +y, the knee Lt below the hip along -z, gravity -z.
inline ChainModel apalChain(double Lt) {
  ChainModel m;
  m.name = "apal";
  ChainJoint hip;
  hip.name = "hip";
  hip.link = "thigh";
  hip.axis = Eigen::Vector3d::UnitY();
  ChainJoint knee = hip;
  knee.name = "knee";
  knee.link = "shank";
  knee.parent_p_joint_m = Eigen::Vector3d(0.0, 0.0, -Lt);
  m.joints = {hip, knee};
  return m;
}

inline Eigen::Matrix3d randomRotation(std::mt19937_64& gen) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond quat(n(gen), n(gen), n(gen), n(gen));
  return quat.normalized().toRotationMatrix();
}

inline Eigen::Vector3d randomUnit(std::mt19937_64& gen) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Vector3d(n(gen), n(gen), n(gen)).normalized();
}

// A physically valid inertia about the COM: principal moments obeying the triangle inequality,
// turned by a random rotation.
inline Eigen::Matrix3d randomInertia(std::mt19937_64& gen) {
  std::uniform_real_distribution<double> u(0.01, 0.5);
  const double a = u(gen), b = u(gen);
  std::uniform_real_distribution<double> c(std::abs(a - b) + 1e-3, a + b);
  const Eigen::Matrix3d R = randomRotation(gen);
  return R * Eigen::Vector3d(a, b, c(gen)).asDiagonal() * R.transpose();
}

inline ChainModel randomChain(std::mt19937_64& gen, int dof) {
  std::uniform_real_distribution<double> offset(-0.4, 0.4);
  ChainModel m;
  m.name = "random";
  m.gravity_mps2 = 9.81 * randomUnit(gen);
  for (int i = 0; i < dof; ++i) {
    ChainJoint j;
    j.name = "j" + std::to_string(i);
    j.link = "l" + std::to_string(i);
    j.parent_R_joint = randomRotation(gen);
    j.parent_p_joint_m = Eigen::Vector3d(offset(gen), offset(gen), offset(gen));
    j.axis = randomUnit(gen);
    j.armature = i % 2 == 1;
    m.joints.push_back(j);
  }
  return m;
}

inline Eigen::VectorXd randomPhysicalParameters(std::mt19937_64& gen, const ChainModel& m) {
  std::uniform_real_distribution<double> mass(0.2, 8.0), com(-0.3, 0.3), pos(0.01, 1.0);
  Eigen::VectorXd phi(m.standardParameterCount());
  const std::vector<JointParameterLayout> layout = m.layout();
  for (int i = 0; i < m.dof(); ++i) {
    const JointParameterLayout& l = layout[static_cast<std::size_t>(i)];
    phi.segment<kLinkParams>(l.link) = linkParameters(mass(gen), Eigen::Vector3d(com(gen), com(gen), com(gen)), randomInertia(gen));
    if (l.friction >= 0) phi.segment<2>(l.friction) << pos(gen), pos(gen);
    if (l.armature >= 0) phi[l.armature] = pos(gen);
  }
  return phi;
}

}  // namespace exoid::ident::testing
