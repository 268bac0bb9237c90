#include "exoid/ident/model/newton_euler.hpp"

#include "exoid/ident/leg/regressor.hpp"
#include "random_chain.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace exoid::ident {
namespace {

using testing::apalChain;
using testing::randomChain;
using testing::randomInertia;
using testing::randomPhysicalParameters;
using testing::randomRotation;

// Both sides sum O(10^2) products of O(1..100) factors in double precision: a few 1e-14
// relative is their roundoff; 1e-12 is the bar and leaves a factor of ~10.
constexpr double kRelTol = 1e-12;

// An independent route to the same torques: the chain's kinematics only (no Newton-Euler), the
// power balance qd' tau = dE/dt + friction and armature power, along a smooth path through the
// state. E = kinetic + potential, from each link's pose, COM velocity and angular velocity.
struct LinkBody {
  double m;
  Eigen::Vector3d c;   // COM, link frame
  Eigen::Matrix3d Ic;  // about the COM, link frame
};

double energy(const ChainModel& model, const std::vector<LinkBody>& bodies, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  // Link poses and their derivatives by finite differences would be circular; use the chain's
  // own velocity recursion in the world frame instead (pure kinematics).
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();
  double e = 0.0;
  for (int i = 0; i < model.dof(); ++i) {
    const ChainJoint& j = model.joints[static_cast<std::size_t>(i)];
    const Eigen::Vector3d p_joint = p + R * j.parent_p_joint_m;
    v = v + w.cross(p_joint - p);
    const Eigen::Matrix3d R_joint = R * j.parent_R_joint;
    w = w + R_joint * j.axis * qd[i];
    R = R_joint * Eigen::AngleAxisd(q[i], j.axis).toRotationMatrix();
    p = p_joint;
    const LinkBody& b = bodies[static_cast<std::size_t>(i)];
    const Eigen::Vector3d com = p + R * b.c;
    const Eigen::Vector3d v_com = v + w.cross(R * b.c);
    const Eigen::Matrix3d I_world = R * b.Ic * R.transpose();
    e += 0.5 * b.m * v_com.squaredNorm() + 0.5 * w.dot(I_world * w) - b.m * model.gravity_mps2.dot(com);
  }
  return e;
}

TEST(ChainRegressor, PowerBalanceOnRandomSpatialChains) {
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    ChainModel model = randomChain(gen, 6);
    for (ChainJoint& j : model.joints) j.friction = j.armature = false;  // conservative: power = dE/dt
    std::vector<LinkBody> bodies;
    Eigen::VectorXd phi(model.standardParameterCount());
    for (int i = 0; i < model.dof(); ++i) {
      LinkBody b{0.5 + 3.0 * std::abs(u(gen)), 0.3 * Eigen::Vector3d(u(gen), u(gen), u(gen)), randomInertia(gen)};
      phi.segment<kLinkParams>(kLinkParams * i) = linkParameters(b.m, b.c, b.Ic);
      bodies.push_back(b);
    }
    // q(t) = q0 + qd0 t + qdd0 t^2 / 2 around t = 0; dE/dt by a 4th-order central difference.
    Eigen::VectorXd q0(6), qd0(6), qdd0(6);
    for (int i = 0; i < 6; ++i) {
      q0[i] = 3.0 * u(gen);
      qd0[i] = 2.0 * u(gen);
      qdd0[i] = 5.0 * u(gen);
    }
    auto at = [&](double t) { return energy(model, bodies, q0 + qd0 * t + 0.5 * qdd0 * t * t, qd0 + qdd0 * t); };
    const double h = 1e-3;
    const double dEdt = (8.0 * (at(h) - at(-h)) - (at(2 * h) - at(-2 * h))) / (12.0 * h);
    const double power = qd0.dot(chainRegressor(model, q0, qd0, qdd0) * phi);
    // The difference's truncation error ~ h^4 E^(5) / 30 (a few 1e-11 here) dominates roundoff;
    // 1e-8 of the power's scale separates it from any real error (a wrong term is O(1)).
    const double scale = std::max(1.0, std::abs(power));
    EXPECT_NEAR(power, dEdt, 1e-8 * scale) << "trial " << trial;
  }
}

// The recursive Newton-Euler inverse dynamics is the regressor times phi, on random spatial chains
// with friction and armature, on a base that accelerates and turns: two computations of the same
// torque (O(dof) wrenches against O(dof^2) projections), agreeing to rounding.
TEST(ChainRegressor, NewtonEulerInverseDynamicsIsTheRegressorTimesPhi) {
  std::mt19937_64 gen(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const ChainModel model = randomChain(gen, 1 + trial % 7);
    const Eigen::VectorXd phi = testing::randomPhysicalParameters(gen, model);
    const int n = model.dof();
    Eigen::VectorXd q(n), qd(n), qdd(n), tau(n);
    for (int i = 0; i < n; ++i) {
      q[i] = 3.0 * u(gen);
      qd[i] = 2.0 * u(gen);
      qdd[i] = 5.0 * u(gen);
    }
    ChainBaseMotion base;
    base.specific_force_mps2 = Eigen::Vector3d(u(gen), u(gen), 9.81 + u(gen));
    base.omega_radps = Eigen::Vector3d(u(gen), u(gen), u(gen));
    base.alpha_radps2 = 3.0 * Eigen::Vector3d(u(gen), u(gen), u(gen));
    ChainRegressorWorkspace work;
    chainInverseDynamicsInto(model, q, qd, qdd, base, phi, work, tau);
    const Eigen::VectorXd expected = chainRegressor(model, q, qd, qdd, base) * phi;
    EXPECT_LT((tau - expected).cwiseAbs().maxCoeff(), 1e-12 * std::max(1.0, expected.cwiseAbs().maxCoeff())) << "trial " << trial;
  }
}

// The APAL leg as a chain: hip and knee about +y (x anterior, z up), links hanging along -z at
// q = 0, the knee Lt below the hip. Its standard parameters group into the paper's X.

// docs/paper.md, "Modelling facts": Mx = -mz, My = -mx, J = Iyy about the joint, the shank's
// mass carried at Lt by the thigh. Layout per joint: 10 link parameters, fc, fv.
ParamVector apalX(const Eigen::VectorXd& phi, double Lt) {
  const auto t = phi.segment<12>(0), s = phi.segment<12>(12);
  const double ms = s[0], Js = s[7];
  ParamVector x;
  x << -t[3] + ms * Lt, -t[1], t[7] + ms * Lt * Lt + Js, t[10], t[11], -s[3], -s[1], Js, s[10], s[11];
  return x;
}

TEST(ChainRegressor, ApalLegEqualsTheHandWrittenRegressorOnAMovingBase) {
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const double Lt = 0.3 + 0.2 * std::abs(u(gen));
    const ChainModel model = apalChain(Lt);
    const Eigen::VectorXd phi = randomPhysicalParameters(gen, model);
    const Eigen::Vector2d q(2 * u(gen), 2 * u(gen)), qd(6 * u(gen), 6 * u(gen)), qdd(60 * u(gen), 60 * u(gen));
    BaseMotion base{3.0 * u(gen), 9.81 + 3.0 * u(gen), 2.0 * u(gen), 20.0 * u(gen)};
    if (trial % 2 == 0) base = BaseMotion::still(9.81);
    ChainBaseMotion chain_base;
    chain_base.specific_force_mps2 = Eigen::Vector3d(base.f_x_mps2, 0.0, base.f_z_mps2);
    chain_base.omega_radps = Eigen::Vector3d(0.0, base.omega_radps, 0.0);
    chain_base.alpha_radps2 = Eigen::Vector3d(0.0, base.alpha_radps2, 0.0);
    const Eigen::Vector2d generic = chainRegressor(model, q, qd, qdd, chain_base) * phi;
    RegressorRow hip, knee;
    regressorRows(LegConstants{Lt, 9.81}, q, qd, qdd, base, hip, knee);
    const ParamVector x = apalX(phi, Lt);
    const double scale = std::max(1.0, generic.cwiseAbs().maxCoeff());
    EXPECT_NEAR(generic[0], hip.dot(x), kRelTol * scale) << "trial " << trial;
    EXPECT_NEAR(generic[1], knee.dot(x), kRelTol * scale) << "trial " << trial;
  }
}

TEST(ChainRegressor, FrictionAndArmatureActOnTheirOwnJoint) {
  ChainModel model = apalChain(0.45);
  model.joints[1].armature = true;
  const Eigen::MatrixXd Y = chainRegressor(model, Eigen::Vector2d(0.1, 0.2), Eigen::Vector2d(-1.5, 0.0), Eigen::Vector2d(3.0, 4.0));
  const std::vector<JointParameterLayout> l = model.layout();
  EXPECT_EQ(Y(0, l[0].friction), -1.0);
  EXPECT_EQ(Y(0, l[0].friction + 1), -1.5);
  EXPECT_EQ(Y(1, l[1].friction), 0.0);  // sgn(0) = 0
  EXPECT_EQ(Y(1, l[1].armature), 4.0);
  EXPECT_EQ(Y(0, l[1].armature), 0.0);
  EXPECT_EQ(Y(1, l[0].friction), 0.0);
  EXPECT_EQ(Y.block(1, 0, 1, kLinkParams).norm(), 0.0);  // the knee carries no thigh
}

TEST(ChainRegressor, NamesFollowTheLayout) {
  ChainModel model = apalChain(0.45);
  model.joints[1].armature = true;
  const std::vector<std::string> names = model.standardParameterNames();
  ASSERT_EQ(static_cast<int>(names.size()), model.standardParameterCount());
  EXPECT_EQ(names[0], "thigh.m");
  EXPECT_EQ(names[9], "thigh.Izz");
  EXPECT_EQ(names[10], "hip.fc");
  EXPECT_EQ(names[model.layout()[1].armature], "knee.Ia");
}

TEST(ChainRegressor, RejectsMalformedModelsAndStates) {
  ChainModel model = apalChain(0.45);
  model.joints[1].axis = Eigen::Vector3d(0.0, 2.0, 0.0);
  EXPECT_THROW(model.validate(), std::invalid_argument);
  model = apalChain(0.45);
  model.joints[1].name = "hip";
  EXPECT_THROW(model.validate(), std::invalid_argument);
  model = apalChain(0.45);
  model.joints[0].parent_R_joint(0, 0) = -1.0;  // a reflection
  EXPECT_THROW(model.validate(), std::invalid_argument);
  EXPECT_THROW(ChainModel{}.validate(), std::invalid_argument);
  try {
    chainRegressor(apalChain(0.45), Eigen::Vector3d::Zero(), Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero());
    ADD_FAILURE() << "a 3-vector q for a 2-joint chain was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("expected 2 entries in q"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace exoid::ident
