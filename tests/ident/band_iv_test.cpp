// Instrumental variables from the motion's band against their truths, on every leg (the APAL leg in
// its X, a hip-knee-ankle chain in its base parameters): exact on exact data, and unbiased over 50
// seeds of encoder noise where least squares in the same band is attenuated.
#include "exoid/ident/estimators/band_iv.hpp"

#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/signals/band.hpp"
#include "random_chain.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

namespace exoid::ident {
namespace {

// A leg, an exact 10 s record of it and its true parameters; `noisy_coulomb`: the Coulomb
// parameters a noise test leaves out, where the leg's noise level shifts them (sgn of noisy
// velocities near reversals: a nonlinear errors-in-variables no instrument undoes).
struct LegCase {
  std::string name;
  Robot robot;
  Dataset exact;
  Eigen::VectorXd truth;
  bool noisy_coulomb = false;
  /// Exactness is checked to 1e-6 of max(|truth|, tolerance_floor): relative on the APAL leg's X,
  /// with a floor on a chain's base parameters, some of which are combinations close to zero.
  double tolerance_floor = 0.0;
};

LegCase apalLeg() {
  return {"apal", twoLinkLeg(test::kLeg), test::multisineRecord(10.0, true, false), toParamVector(defaultLeg()), false, 0.0};
}

LegCase chainLeg() {
  ChainModel model = testing::legChain();
  model.joints[2].armature = true;
  std::mt19937_64 gen(11);
  const Eigen::VectorXd phi = testing::randomPhysicalParameters(gen, model);
  Robot robot = chainRobot(model);
  const Eigen::VectorXd truth = robot.basis.combination * phi;
  return {"leg3 chain", robot, testing::exactChainDataset(model, phi, 10.0, 5), truth, true, 1.0};
}

class BandIvOnEveryLeg : public ::testing::TestWithParam<LegCase (*)()> {};

TEST_P(BandIvOnEveryLeg, IsExactOnExactDataInTheBandChosenFromTheRecord) {
  const LegCase leg = GetParam()();
  SignalOptions o = test::tenHertzParallel();
  o.cutoff_from_data = o.derivative_cutoff_from_data = true;  // identify's default: the band chosen once for rows and instruments
  const Estimate e = solveBandIv({bandIvRows(leg.exact, leg.robot, o, motionBandwidth(leg.exact))});
  ASSERT_EQ(e.summary.status, Status::kConverged) << e.summary.message;
  // From angles alone, as least squares: 1e-6 relative (parallel_processing_test).
  for (int i = 0; i < leg.robot.parameters(); ++i) {
    EXPECT_NEAR(e.x[i], leg.truth[i], 1e-6 * std::max(leg.tolerance_floor, std::abs(leg.truth[i]))) << leg.name << " " << leg.robot.names()[static_cast<std::size_t>(i)];
  }
}

TEST_P(BandIvOnEveryLeg, IsUnbiasedUnderEncoderNoiseWhereLeastSquaresIsNot) {
  // 0.5 mrad (0.03 deg) of white encoder noise on every angle and 0.02 N m of torque noise, 50
  // seeds, the fixed 10 Hz band. Differentiated twice, the encoder noise attenuates least squares'
  // inertial parameters by 3-5 of their standard deviations (the APAL leg's thigh: measured -0.0044,
  // -0.0019, -0.0025 on Mxt, Myt, Jt); iv-band's mean error must lie within the 99 % band of a mean
  // of 50 (2.58 sd / sqrt(50)) on every parameter, and least squares' outside it on at least three
  // (the situation the method is for). On the chain the Coulomb ones are left out: what iv-band
  // does not remove (measured on the APAL leg at 1 mrad: fc1 +0.034 N m for iv-band, +0.040 for LS).
  const LegCase leg = GetParam()();
  const double fm = motionBandwidth(leg.exact);
  const Eigen::Index p = leg.robot.parameters();
  constexpr int kSeeds = 50;
  Eigen::MatrixXd ls(p, kSeeds), iv(p, kSeeds);
  std::mt19937_64 gen(20261202);
  std::normal_distribution<double> angle(0.0, 5e-4), torque(0.0, 0.02);
  for (int k = 0; k < kSeeds; ++k) {
    Dataset d = leg.exact;
    d.q_rad += Eigen::MatrixXd::NullaryExpr(d.size(), d.dof(), [&] { return angle(gen); });
    d.tau_Nm += Eigen::MatrixXd::NullaryExpr(d.size(), d.dof(), [&] { return torque(gen); });
    const BandIvRows rows = bandIvRows(d, leg.robot, test::tenHertzParallel(), fm);
    ls.col(k) = solveLeastSquares(rows.H, rows.y).x - leg.truth;
    iv.col(k) = solveBandIv({rows}).x - leg.truth;
  }
  const auto meanAndSd = [](const Eigen::MatrixXd& z, Eigen::Index i, double& mean, double& sd) {
    mean = z.row(i).mean();
    sd = std::sqrt((z.row(i).array() - mean).square().sum() / (static_cast<double>(z.cols()) - 1.0));
  };
  int ls_biased = 0;
  for (Eigen::Index i = 0; i < p; ++i) {
    double m_iv, sd_iv, m_ls, sd_ls;
    meanAndSd(iv, i, m_iv, sd_iv);
    meanAndSd(ls, i, m_ls, sd_ls);
    const std::string& name = leg.robot.names()[static_cast<std::size_t>(i)];
    const bool coulomb = std::find(leg.robot.coulomb.begin(), leg.robot.coulomb.end(), static_cast<int>(i)) != leg.robot.coulomb.end();
    const double band = 2.58 / std::sqrt(double(kSeeds));
    if (!(coulomb && leg.noisy_coulomb)) {
      EXPECT_LT(std::abs(m_iv), band * sd_iv) << leg.name << " " << name << " iv mean " << m_iv << " sd " << sd_iv;
    }
    if (std::abs(m_ls) > band * sd_ls) ++ls_biased;
    std::printf("[ info ] %s %s: LS mean %.3g (sd %.3g), iv-band mean %.3g (sd %.3g)\n", leg.name.c_str(), name.c_str(), m_ls, sd_ls,
                m_iv, sd_iv);
  }
  EXPECT_GE(ls_biased, 3) << leg.name;
}

TEST_P(BandIvOnEveryLeg, RefusesWhatItCannotDo) {
  const LegCase leg = GetParam()();
  SignalOptions paper = test::tenHertzParallel();
  paper.processing = Processing::kPaper;
  test::expectInvalidArgumentMentioning([&] { bandIvRows(leg.exact, leg.robot, paper, 2.0); }, "parallel");
  test::expectInvalidArgumentMentioning([&] { bandIvRows(leg.exact, leg.robot, test::tenHertzParallel(), 600.0); }, "cutoff");
  test::expectInvalidArgumentMentioning([&] { solveBandIv({}); }, "no records");
}

INSTANTIATE_TEST_SUITE_P(Legs, BandIvOnEveryLeg, ::testing::Values(&apalLeg, &chainLeg),
                         [](const ::testing::TestParamInfo<LegCase (*)()>& leg) { return leg.index == 0 ? "Apal" : "Leg3Chain"; });

}  // namespace
}  // namespace exoid::ident
