#include "exoid/ident/design/robot_excitation.hpp"

#include "random_chain.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace exoid::ident {
namespace {


Eigen::VectorXd nominal() {
  Eigen::VectorXd phi(24);
  phi.segment<10>(0) = linkParameters(9.0, {0.0, 0.0, -0.2}, Eigen::Vector3d(0.15, 0.15, 0.03).asDiagonal());
  phi.segment<2>(10) << 1.0, 0.5;
  phi.segment<10>(12) = linkParameters(4.0, {0.0, 0.0, -0.2}, Eigen::Vector3d(0.06, 0.06, 0.01).asDiagonal());
  phi.segment<2>(22) << 0.7, 0.3;
  return phi;
}

ChainExcitationLimits limits() {
  ChainExcitationLimits l;
  l.q_min_rad = Eigen::Vector2d(-1.2, 0.05);
  l.q_max_rad = Eigen::Vector2d(0.4, 1.9);
  l.qd_max_radps = Eigen::Vector2d(3.0, 3.0);
  l.qdd_max_radps2 = Eigen::Vector2d(30.0, 30.0);
  l.tau_max_Nm = Eigen::Vector2d(120.0, 60.0);
  return l;
}

// A design starts and ends at rest, stays inside every limit (checked on 1000 samples), is the
// same for the same seed, and scores as its own score function says.
TEST(ChainExcitation, FeasibleAtRestAtTheEndsAndDeterministic) {
  const ChainModel model = testing::apalChain(0.45);
  const BaseParameters base = baseParameters(model);
  ExcitationOptions o;
  o.restarts = 2;
  o.max_evaluations = 400;
  const ChainExcitationDesign a = designChainExcitation(o, model, base, nominal(), limits());
  const ChainExcitationDesign b = designChainExcitation(o, model, base, nominal(), limits());
  EXPECT_EQ(a.trajectory.a_rad, b.trajectory.a_rad);
  EXPECT_EQ(a.trajectory.b_rad, b.trajectory.b_rad);
  EXPECT_EQ(a.score.worst_violation, 0.0) << a.score.worst_violation_name;
  Eigen::VectorXd q, qd, qdd;
  a.trajectory.at(0.0, q, qd, qdd);
  EXPECT_LE(qd.cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LE(qdd.cwiseAbs().maxCoeff(), 1e-10);
  a.trajectory.at(1.0 / a.trajectory.f0_hz, q, qd, qdd);
  EXPECT_LE(qd.cwiseAbs().maxCoeff(), 1e-9);
  const ChainExcitationScore s = scoreChainExcitation(model, base, a.trajectory, nominal(), limits(), 1000);
  EXPECT_EQ(s.condition_number, a.score.condition_number);
  EXPECT_TRUE(std::isfinite(s.condition_number));
  // A motion that leaves the knee's range is scored as a violation naming it.
  core::FourierSeries wide = a.trajectory;
  wide.offset_rad[1] = 2.5;
  EXPECT_EQ(scoreChainExcitation(model, base, wide, nominal(), limits(), 200).worst_violation_name.rfind("q_max[knee]", 0), 0u);
  o.hip_locked = true;
  EXPECT_THROW(designChainExcitation(o, model, base, nominal(), limits()), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::ident
