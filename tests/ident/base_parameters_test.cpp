#include "exoid/ident/model/base_parameters.hpp"

#include "exoid/ident/model/newton_euler.hpp"
#include "random_chain.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <random>

namespace exoid::ident {
namespace {

using testing::apalChain;


// The paper's X as rows over the APAL chain's 24 standard parameters (docs/paper.md, "Modelling
// facts": Mx = -mz, My = -mx, J = Iyy about the joint, the shank's mass carried at Lt).
Eigen::MatrixXd paperGrouping(double Lt) {
  // thigh: 0 m, 1 mx, 2 my, 3 mz, 7 Iyy, 10 fc, 11 fv; shank: +12.
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(10, 24);
  G(0, 3) = -1.0, G(0, 12) = Lt;                   // Mxt
  G(1, 1) = -1.0;                                  // Myt
  G(2, 7) = 1.0, G(2, 12) = Lt * Lt, G(2, 19) = 1.0;  // Jt
  G(3, 10) = 1.0;                                  // fc1
  G(4, 11) = 1.0;                                  // fv1
  G(5, 15) = -1.0;                                 // Mxs
  G(6, 13) = -1.0;                                 // Mys
  G(7, 19) = 1.0;                                  // Js
  G(8, 22) = 1.0;                                  // fc2
  G(9, 23) = 1.0;                                  // fv2
  return G;
}

int rankOf(const Eigen::MatrixXd& A) {
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  qr.setThreshold(1e-9);
  return static_cast<int>(qr.rank());
}

TEST(BaseParameters, ApalLegHasThePapersTenCombinations) {
  const double Lt = 0.45;
  const BaseParameters b = baseParameters(apalChain(Lt));
  EXPECT_EQ(b.rank, 10);
  const Eigen::MatrixXd G = paperGrouping(Lt);
  ASSERT_EQ(rankOf(G), 10);
  Eigen::MatrixXd both(20, 24);
  both << b.combination, G;
  EXPECT_EQ(rankOf(both), 10) << "the paper's X and the QR's base parameters span different spaces";
  // What the planar leg cannot show: the thigh's mass (at the hip axis), my and every inertia
  // entry but Iyy of both links; the shank's mass acts only through the thigh's combinations.
  EXPECT_EQ(b.no_effect.size(), 13u);
  ASSERT_EQ(b.regrouped.size(), 1u);
  EXPECT_EQ(b.regrouped[0].first, 12);  // shank.m
}

TEST(BaseParameters, BaseRegressorTimesBaseParametersIsTheTorque) {
  std::mt19937_64 gen(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ChainModel model = apalChain(0.4);
  model.joints.push_back(model.joints[1]);
  model.joints[2].name = "ankle";
  model.joints[2].link = "foot";
  model.joints[2].parent_p_joint_m = Eigen::Vector3d(0.02, 0.0, -0.42);
  model.joints[2].armature = true;
  const BaseParameters b = baseParameters(model);
  Eigen::VectorXd phi(model.standardParameterCount());
  for (Eigen::Index k = 0; k < phi.size(); ++k) phi[k] = u(gen);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Vector3d q(3 * u(gen), 3 * u(gen), 3 * u(gen)), qd(3 * u(gen), 3 * u(gen), 3 * u(gen)),
        qdd(30 * u(gen), 30 * u(gen), 30 * u(gen));
    const Eigen::MatrixXd Y = chainRegressor(model, q, qd, qdd);
    const Eigen::VectorXd tau = Y * phi, tau_base = b.baseRegressor(Y) * (b.combination * phi);
    EXPECT_LE((tau - tau_base).cwiseAbs().maxCoeff(), 1e-11 * std::max(1.0, tau.cwiseAbs().maxCoeff()));
  }
}

TEST(BaseParameters, RowSpaceIsTheRegressorsWhateverTheSeed) {
  // The base parameters' space is unique: the orthogonal complement of the regressor's null space
  // (from an SVD here, an independent factorisation); only the pivots may depend on the states.
  ChainModel model = apalChain(0.45);
  model.joints[1].axis = Eigen::Vector3d(0.0, 0.6, 0.8);  // a non-planar knee
  BaseParameterOptions o;
  const BaseParameters a = baseParameters(model, o);
  o.seed = 99;
  const BaseParameters c = baseParameters(model, o);
  EXPECT_EQ(a.rank, c.rank);
  Eigen::MatrixXd both(a.rank + c.rank, a.combination.cols());
  both << a.combination, c.combination;
  EXPECT_EQ(rankOf(both), a.rank);
  Eigen::MatrixXd W(400 * model.dof(), model.standardParameterCount());
  std::mt19937_64 gen(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int s = 0; s < 400; ++s) {
    const Eigen::Vector2d q(3 * u(gen), 3 * u(gen)), qd(3 * u(gen), 3 * u(gen)), qdd(30 * u(gen), 30 * u(gen));
    W.middleRows(2 * s, 2) = chainRegressor(model, q, qd, qdd);
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(W, Eigen::ComputeFullV);
  const Eigen::VectorXd sv = svd.singularValues();
  const int rank = static_cast<int>((sv.array() > 1e-9 * sv[0]).count());
  EXPECT_EQ(rank, a.rank);
  const Eigen::MatrixXd null_space = svd.matrixV().rightCols(W.cols() - rank);
  EXPECT_LE((a.combination * null_space).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(BaseParameters, SameSeedSameBytesAndReadableNames) {
  const BaseParameters a = baseParameters(apalChain(0.45)), b = baseParameters(apalChain(0.45));
  EXPECT_EQ(a.combination, b.combination);
  EXPECT_EQ(a.names, b.names);
  EXPECT_EQ(a.combinations, b.combinations);
  const bool has_regrouped_name = std::any_of(a.combinations.begin(), a.combinations.end(), [](const std::string& n) {
    return n.find("shank.m") != std::string::npos && n.find(" + ") != std::string::npos;
  });
  EXPECT_TRUE(has_regrouped_name) << "the shank's mass is written out inside a thigh combination";
  // Each label: the leading standard parameter and how many terms it regroups; distinct.
  ASSERT_EQ(a.names.size(), a.combinations.size());
  for (std::size_t i = 0; i < a.names.size(); ++i) {
    const std::string lead = a.combinations[i].substr(0, a.combinations[i].find(' '));
    EXPECT_EQ(a.names[i].rfind(lead, 0), 0u) << a.names[i];
    const long others = (a.combination.row(static_cast<Eigen::Index>(i)).array() != 0.0).count() - 1;
    EXPECT_EQ(a.names[i], others == 0 ? lead : lead + " + " + std::to_string(others) + (others == 1 ? " term" : " terms"));
  }
  EXPECT_EQ(std::set<std::string>(a.names.begin(), a.names.end()).size(), a.names.size());
  BaseParameterOptions bad;
  bad.samples = 0;
  EXPECT_THROW(baseParameters(apalChain(0.45), bad), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::ident
