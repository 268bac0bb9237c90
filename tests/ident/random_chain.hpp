#pragma once
// The chains the chain tests share: the APAL leg's planar hip-knee chain, random serial chains,
// physically valid parameters for them, and a 3-joint leg under a chain rig's controller.
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/model/chain.hpp"
#include "exoid/ident/model/newton_euler.hpp"
#include "exoid/ident/model/closed_loop.hpp"
#include "exoid/ident/model/robot.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <functional>
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

// A sagittal hip-knee-ankle leg: the APAL chain with a foot 0.43 m below the knee.
inline ChainModel legChain() {
  ChainModel m = apalChain(0.45);
  m.name = "leg";
  ChainJoint ankle = m.joints[1];
  ankle.name = "ankle";
  ankle.link = "foot";
  ankle.parent_p_joint_m = Eigen::Vector3d(0.0, 0.0, -0.43);
  m.joints.push_back(ankle);
  return m;
}

// An exact 1 kHz record of the chain: each joint a two-frequency motion (0.3-1.7 Hz and 2.3x that)
// drawn from `seed`, torque = regressor x phi at the analytic states (on a still base, or on
// `base`'s motion at each time); columns t, q_<joint>, tau_<joint>, and qd_, qdd_ when asked.
inline Dataset exactChainDataset(const ChainModel& m, const Eigen::VectorXd& phi, double duration_s, std::uint64_t seed,
                                 bool with_derivatives = false,
                                 const std::function<ChainBaseMotion(double)>& base = nullptr) {
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> amp(0.3, 0.7), freq(0.3, 1.7), phase(0.0, 6.28);
  const auto n = static_cast<Eigen::Index>(std::llround(duration_s * 1000.0));
  const Eigen::Index dof = m.dof();
  Dataset d;
  d.joints = m.jointNames();
  d.t_s = Eigen::VectorXd::LinSpaced(n, 0.0, 1e-3 * static_cast<double>(n - 1));
  d.q_rad.resize(n, dof);
  d.tau_Nm.resize(n, dof);
  Eigen::MatrixXd qd(n, dof), qdd(n, dof);
  for (Eigen::Index j = 0; j < dof; ++j) {
    const double a1 = amp(gen), w1 = 2 * M_PI * freq(gen), p1 = phase(gen), a2 = 0.3 * amp(gen), w2 = 2.3 * w1, p2 = phase(gen);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double t = d.t_s[i];
      d.q_rad(i, j) = a1 * std::sin(w1 * t + p1) + a2 * std::sin(w2 * t + p2);
      qd(i, j) = a1 * w1 * std::cos(w1 * t + p1) + a2 * w2 * std::cos(w2 * t + p2);
      qdd(i, j) = -a1 * w1 * w1 * std::sin(w1 * t + p1) - a2 * w2 * w2 * std::sin(w2 * t + p2);
    }
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::VectorXd q = d.q_rad.row(i).transpose(), v = qd.row(i).transpose(), a = qdd.row(i).transpose();
    const ChainBaseMotion b = base ? base(d.t_s[i]) : ChainBaseMotion::still(m);
    d.tau_Nm.row(i) = (chainRegressor(m, q, v, a, b) * phi).transpose();
  }
  if (with_derivatives) {
    d.qd_radps = qd;
    d.qdd_radps2 = qdd;
  }
  return d;
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

// A sagittal hip-knee-ankle chain in its base parameters under a chain rig's controller: PD on the
// measured velocity (each joint a 4 Hz loop, damping 0.7, on its diagonal inertia at the start)
// with a 100 Hz motor lag, the model's feedforward on a smooth two-frequency reference per joint.
struct ChainUnderPd {
  Robot robot;
  Eigen::VectorXd phi, theta;
  Controller controller;
  Reference reference;

  explicit ChainUnderPd(double duration_s) {
    ChainModel model = legChain();
    model.joints[2].armature = true;
    std::mt19937_64 gen(11);
    phi = randomPhysicalParameters(gen, model);
    robot = chainRobot(model);
    theta = robot.basis.combination * phi;
    const Dataset motion = exactChainDataset(model, phi, duration_s, 5);
    reference = Reference::fromAngles(motion.t_s, motion.q_rad);
    const Eigen::VectorXd q0 = reference.q_rad.row(0).transpose(), zero = Eigen::VectorXd::Zero(3);
    const double wn = 2.0 * M_PI * 4.0;
    controller.kp_Nm_per_rad.resize(3);
    controller.kd_Nms_per_rad.resize(3);
    for (int j = 0; j < 3; ++j) {
      const double mjj = (chainRegressor(model, q0, zero, Eigen::VectorXd::Unit(3, j)) * phi - chainRegressor(model, q0, zero, zero) * phi)[j];
      controller.kp_Nm_per_rad[j] = mjj * wn * wn;
      controller.kd_Nms_per_rad[j] = 1.4 * wn * mjj;
    }
    controller.derivative = DerivativeSource::kMeasuredVelocity;
    controller.actuator_bandwidth_hz = 100.0;
  }
};

}  // namespace exoid::ident::testing
