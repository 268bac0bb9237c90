#include "exoid/ident/design/identifiability.hpp"

#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/estimators/segmental.hpp"
#include "test_support.hpp"

#include <Eigen/QR>
#include <gtest/gtest.h>

#include <random>

namespace exoid::ident {
namespace {


Eigen::MatrixXd cols(const Eigen::MatrixXd& H, int first, int n) { return H.middleCols(first, n); }

// The findings paper.md reports for the paper's trajectories (10 s at 1 kHz).
TEST(Identifiability, PaperTrajectoriesRankFindings) {
  const LegPhysical leg = defaultLeg();
  for (int id = 1; id <= 4; ++id) {
    const JointSignals s = test::exactRecord(id, leg, test::kLeg.gravity_mps2);
    const Eigen::MatrixXd Hh = jointRegressor(s, Joint::kHip, test::kLeg), Hk = jointRegressor(s, Joint::kKnee, test::kLeg);
    const auto hip = analyzeIdentifiability(cols(Hh, 0, 5), s.tau_Nm.col(0), 0.5);
    const auto knee = analyzeIdentifiability(cols(Hk, 5, 5), s.tau_Nm.col(1), 0.5);
    SCOPED_TRACE("trajectory " + std::to_string(id));
    if (id <= 2) {
      // Hip fixed: the hip equation alone cannot identify the thigh parameters.
      EXPECT_LT(hip.rank, 5);
      EXPECT_FALSE(hip.unidentifiable.empty());
      EXPECT_EQ(knee.rank, 5);
    } else {
      EXPECT_EQ(hip.rank, 5);
    }
    if (id == 4) {
      // q1 + q2 is constant (15 deg): g s12 and g c12 are constant, the knee equation loses rank.
      EXPECT_LT(knee.rank, 5);
    }
    if (id == 1) {
      // paper.md: knee equation rank 5, condition ~250 after column scaling.
      EXPECT_GT(knee.condition_number, 100.0);
      EXPECT_LT(knee.condition_number, 1000.0);
    }
  }
}

TEST(Identifiability, SingleFrequencyMakesInertiaNearlyCollinearWithGravity) {
  const JointSignals s = test::exactRecord(1, defaultLeg(), test::kLeg.gravity_mps2);
  const Eigen::MatrixXd Hk = jointRegressor(s, Joint::kKnee, test::kLeg);
  Eigen::MatrixXd H(Hk.rows(), 3);
  H << Hk.col(kMxs), Hk.col(kMys), Hk.col(kJs);  // qdd2 vs [g s12, g c12] (+ Lt terms, zero here)
  const auto r = analyzeIdentifiability(H, s.tau_Nm.col(1), 0.5);
  EXPECT_GT(r.collinearity_r2[2], 0.999);  // paper.md: R^2 = 0.9999
}

// Least squares reports each column's collinearity from its own pivoted factor (what identify's
// excitation line prints); the identifiability report computes it from an unpivoted QR of its
// own: the two agree to rounding, on a well and on a poorly conditioned record.
TEST(Identifiability, LeastSquaresGivesTheSameCollinearityFromItsOwnFactor) {
  for (int trajectory : {1, 3}) {
    const JointSignals s = test::exactRecord(trajectory, defaultLeg(), test::kLeg.gravity_mps2);
    const Eigen::MatrixXd H = jointRegressor(s, Joint::kKnee, test::kLeg).middleCols(kShankFirst, kGroupSize);
    const IdentifiabilityReport r = analyzeIdentifiability(H, s.tau_Nm.col(1), 0.5);
    LsOptions lo;
    lo.max_condition = 1e300;
    const LsResult ls = solveLeastSquares(H, s.tau_Nm.col(1), lo);
    ASSERT_EQ(ls.rank, H.cols());
    EXPECT_DOUBLE_EQ(ls.condition_number, r.condition_number);
    for (Eigen::Index j = 0; j < H.cols(); ++j) {
      // 1 - R^2 = 1 / [(Hs^T Hs)^-1]_jj: both inverse diagonals to 1e-10 relative (the condition
      // number, <= 1e4 here, times the rounding of two different factorisations).
      EXPECT_NEAR(1.0 - ls.collinearity_r2[j], 1.0 - r.collinearity_r2[j], 1e-10 * (1.0 - r.collinearity_r2[j]) + 1e-15) << trajectory << " " << j;
    }
  }
}

TEST(Identifiability, CramerRaoMatchesMonteCarloLsScatter) {
  // The LS std over many noise draws must match sigma sqrt(diag((H^T H)^-1)). With 400 draws the
  // sample std has relative standard error 1/sqrt(2 * 399) = 3.5 %: allow 5 sigma, 18 %.
  const LegPhysical leg = defaultLeg();
  const JointSignals s = test::exactRecord(1, leg, test::kLeg.gravity_mps2, 2.0);
  const test::LinearProblem pr = test::kneeProblem(s);
  const double sigma = 0.5;
  const auto r = analyzeIdentifiability(pr.H, pr.y, sigma);
  std::mt19937_64 gen(99);
  std::normal_distribution<double> noise(0.0, sigma);
  const int draws = 400;
  Eigen::MatrixXd est(5, draws);
  const auto qr = pr.H.colPivHouseholderQr();
  for (int k = 0; k < draws; ++k) {
    const Eigen::VectorXd y = pr.y + Eigen::VectorXd::NullaryExpr(pr.y.size(), [&] { return noise(gen); });
    est.col(k) = qr.solve(y);
  }
  const Eigen::VectorXd mean = est.rowwise().mean();
  for (int j = 0; j < 5; ++j) {
    const double sd = std::sqrt((est.row(j).array() - mean[j]).square().sum() / (draws - 1));
    EXPECT_NEAR(sd / r.crb_std[j], 1.0, 0.18) << paramName(kShankFirst + j);
  }
}

TEST(Identifiability, RankDeficientBlockReportsInfiniteBounds) {
  Eigen::MatrixXd H = Eigen::MatrixXd::Random(100, 3);
  H.col(1) = H.col(0);
  const auto r = analyzeIdentifiability(H, Eigen::VectorXd::Random(100), 0.1);
  EXPECT_EQ(r.rank, 2);
  EXPECT_TRUE(std::isinf(r.condition_number));
  EXPECT_EQ(r.unidentifiable.size(), 1u);
}

}  // namespace
}  // namespace exoid::ident
