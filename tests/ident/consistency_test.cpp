// Physically consistent least squares against independent truths: every physical leg satisfies
// the conditions (they follow from the definitions); with one bound active the solution is LS
// with that parameter fixed at the bound (a closed form); with the cone active the KKT conditions
// hold (the certificate of optimality of a convex problem); a consistent LS estimate is returned
// untouched; the result is never inconsistent.
#include "exoid/ident/leg/consistency.hpp"

#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/leg/params.hpp"

#include <Eigen/LU>
#include <gtest/gtest.h>

#include <random>

namespace exoid::ident {
namespace {

constexpr double kLt = 0.45;

// A random well-conditioned problem y = H x_true + noise.
struct Problem {
  Eigen::MatrixXd H;
  Eigen::VectorXd y;
};
Problem randomProblem(const Eigen::VectorXd& x_true, double noise, std::uint64_t seed, Eigen::Index rows = 400) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  Problem p{Eigen::MatrixXd(rows, x_true.size()), Eigen::VectorXd(rows)};
  for (Eigen::Index i = 0; i < rows; ++i) {
    for (Eigen::Index j = 0; j < x_true.size(); ++j) p.H(i, j) = n01(gen);
  }
  for (Eigen::Index i = 0; i < rows; ++i) p.y[i] = p.H.row(i).dot(x_true) + noise * n01(gen);
  return p;
}

Eigen::MatrixXd lsCovariance(const Eigen::MatrixXd& H, double sigma) {
  return sigma * sigma * (H.transpose() * H).inverse();
}

TEST(Consistency, EveryPhysicalLegSatisfiesTheConditions) {
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 2000; ++k) {
    LegPhysical leg;
    const double lt = 0.1 + u(gen);
    leg.thigh = {0.5 + 20 * u(gen), lt, -0.2 + 0.6 * u(gen), -0.3 + 0.6 * u(gen), 1e-6 + 0.5 * u(gen)};
    leg.shank = {0.2 + 8 * u(gen), 0.0, -0.2 + 0.6 * u(gen), -0.3 + 0.6 * u(gen), 1e-6 + 0.3 * u(gen)};
    leg.fc_hip_Nm = 3 * u(gen);
    leg.fv_knee_Nms = u(gen);
    const ParamVector x = toParamVector(leg);
    EXPECT_TRUE(ConsistencyConditions(lt).satisfied(x)) << k;
  }
}

TEST(Consistency, TheConeIsTightAPointMassShankOnAMasslessThighLiesOnIt) {
  // Is = 0 (a point mass shank) and a massless, inertia-free thigh: Jt - Js = ms Lt^2 and
  // Js = ms d^2, so (Jt - Js) Js = Lt^2 (ms d)^2 exactly: the condition cannot be tightened.
  LegPhysical leg;
  leg.thigh = {0.0, kLt, 0.1, 0.0, 0.0};
  leg.shank = {3.0, 0.0, 0.25, 0.05, 0.0};
  const ParamVector x = toParamVector(leg);
  const ConsistencyConditions c(kLt);
  EXPECT_NEAR(c.value(6, x), 0.0, 1e-15);
}

TEST(Consistency, AConsistentLeastSquaresEstimateIsReturnedUntouched) {
  const Eigen::VectorXd x_true = toParamVector(defaultLeg());
  const Problem p = randomProblem(x_true, 0.01, 1);
  const LsResult ls = solveLeastSquares(p.H, p.y);
  const ConsistentEstimate c = solveConsistentLeastSquares(p.H, p.y, kLt, ls.x, lsCovariance(p.H, 0.01));
  EXPECT_FALSE(c.constrained);
  EXPECT_EQ(c.x, ls.x);  // bit for bit: <= 1e-9 holds trivially
  for (const ConsistencyCheck& k : c.checks) EXPECT_FALSE(k.violated()) << k.name;
}

TEST(Consistency, OneActiveBoundGivesLeastSquaresWithThatParameterAtTheBound) {
  // fv1 = 0 in truth; noise makes LS negative on some seeds. The constrained optimum is then LS
  // of the other nine columns with fv1 = 0 (the closed form), when those nine are consistent.
  Eigen::VectorXd x_true = toParamVector(defaultLeg());
  x_true[kFv1] = 0.0;
  int checked = 0;
  for (std::uint64_t seed = 1; seed <= 40 && checked < 5; ++seed) {
    const Problem p = randomProblem(x_true, 1.0, seed);
    const LsResult ls = solveLeastSquares(p.H, p.y);
    if (ls.x[kFv1] >= 0.0) continue;
    Eigen::MatrixXd H9(p.H.rows(), 9);
    H9 << p.H.leftCols(kFv1), p.H.rightCols(kNumParams - kFv1 - 1);
    const Eigen::VectorXd x9 = solveLeastSquares(H9, p.y).x;
    Eigen::VectorXd expected(kNumParams);
    expected << x9.head(kFv1), 0.0, x9.tail(kNumParams - kFv1 - 1);
    if (!ConsistencyConditions(kLt).satisfied(expected)) continue;
    const ConsistentEstimate c = solveConsistentLeastSquares(p.H, p.y, kLt, ls.x, lsCovariance(p.H, 1.0));
    ASSERT_TRUE(c.constrained);
    // Tolerance: the interior point stops at a relative duality gap of 1e-14 of ||y||^2; the
    // parameter error that leaves is below sqrt(gap / lambda_min) ~ 1e-7 * scale here.
    EXPECT_LT((c.x - expected).cwiseAbs().maxCoeff(), 1e-7 * x_true.cwiseAbs().maxCoeff()) << "seed " << seed;
    EXPECT_TRUE(c.checks[1].active);  // fv1 >= 0
    ++checked;
  }
  EXPECT_GE(checked, 3);
}

TEST(Consistency, AnActiveConeSatisfiesTheKktConditions) {
  // A shank whose first moment is too large for its inertia: LS violates the cone.
  Eigen::VectorXd x_true = toParamVector(defaultLeg());
  const double l2 = kLt * kLt;
  x_true[kJt] = x_true[kJs] + 0.5 * l2 * (x_true[kMxs] * x_true[kMxs] + x_true[kMys] * x_true[kMys]) / x_true[kJs];
  const ConsistencyConditions cond(kLt);
  ASSERT_LT(cond.value(6, x_true), 0.0);
  const Problem p = randomProblem(x_true, 1e-3, 7);
  const LsResult ls = solveLeastSquares(p.H, p.y);
  const ConsistentEstimate c = solveConsistentLeastSquares(p.H, p.y, kLt, ls.x, lsCovariance(p.H, 1e-3));
  ASSERT_TRUE(c.constrained);
  EXPECT_TRUE(cond.satisfied(c.x));
  EXPECT_TRUE(c.checks[6].active);
  EXPECT_TRUE(c.checks[6].significant(2.0));
  // KKT: H^T (y - H x) = -lambda grad g (cost gradient H^T H x - H^T y = lambda grad g), lambda >= 0.
  const Eigen::VectorXd cost_grad = p.H.transpose() * (p.H * c.x - p.y);
  const Eigen::VectorXd dg = cond.gradient(6, c.x);
  const double lambda = cost_grad.dot(dg) / dg.squaredNorm();
  EXPECT_GT(lambda, 0.0);
  EXPECT_LT((cost_grad - lambda * dg).norm(), 1e-6 * cost_grad.norm());
}

TEST(Consistency, NeverInconsistentOnRandomProblems) {
  std::mt19937_64 gen(3);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (std::uint64_t seed = 0; seed < 100; ++seed) {
    Eigen::VectorXd x(kNumParams);
    for (int j = 0; j < kNumParams; ++j) x[j] = 0.1 * n01(gen);
    const Problem p = randomProblem(x, 0.05, 100 + seed, 60);
    const LsResult ls = solveLeastSquares(p.H, p.y);
    const ConsistentEstimate c = solveConsistentLeastSquares(p.H, p.y, kLt, ls.x, lsCovariance(p.H, 0.05));
    EXPECT_TRUE(ConsistencyConditions(kLt).satisfied(c.x)) << "seed " << seed;
  }
}

TEST(Consistency, SignificanceIsInStandardErrors) {
  ConsistencyCheck k;
  k.name = "fv1 >= 0";
  k.value = -0.0032;
  k.standard_error = 0.002;
  EXPECT_DOUBLE_EQ(k.t(), -1.6);
  EXPECT_FALSE(k.significant(2.0));
  k.standard_error = 0.001;
  EXPECT_TRUE(k.significant(2.0));
  ConsistentEstimate e;
  e.checks.push_back(k);
  ASSERT_EQ(e.significantViolations(2.0).size(), 1u);
  EXPECT_NE(e.significantViolations(2.0)[0].find("fv1 >= 0 violated by 3.2 standard errors"), std::string::npos);
}

TEST(Consistency, BadInputIsRefused) {
  const Problem p = randomProblem(toParamVector(defaultLeg()), 0.01, 1);
  const Eigen::MatrixXd C = lsCovariance(p.H, 0.01);
  EXPECT_THROW(solveConsistentLeastSquares(p.H.leftCols(9), p.y, kLt, Eigen::VectorXd::Zero(9), C.topLeftCorner(9, 9)),
               std::invalid_argument);
  EXPECT_THROW(solveConsistentLeastSquares(p.H, p.y, 0.0, Eigen::VectorXd::Zero(10), C), std::invalid_argument);
  EXPECT_THROW(solveConsistentLeastSquares(p.H, p.y.head(10), kLt, Eigen::VectorXd::Zero(10), C), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::ident
