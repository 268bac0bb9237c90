#include "exoid/ident/estimators/rls.hpp"

#include "exoid/ident/estimators/least_squares.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include <cmath>
#include <random>

namespace exoid::ident {
namespace {

TEST(Rls, WithoutForgettingConvergesToLeastSquares) {
  // RLS with lambda = 1 and x0 = 0 is exactly ridge regression (H^T H + I / p0)^-1 H^T y; it
  // differs from LS by O(1 / (p0 sigma_min(H)^2)) ~ 1e-6 / 1800 relative here. Roundoff of the
  // covariance form is ~p0 * eps = 1e-10 relative, so 1e-8 against the ridge solution.
  std::mt19937_64 gen(3);
  std::normal_distribution<double> n01(0.0, 1.0);
  const Eigen::Index N = 2000, p = 5;
  const Eigen::MatrixXd H = Eigen::MatrixXd::NullaryExpr(N, p, [&] { return n01(gen); });
  const Eigen::VectorXd y = H * Eigen::VectorXd::LinSpaced(p, -2.0, 3.0) +
                            0.5 * Eigen::VectorXd::NullaryExpr(N, [&] { return n01(gen); });
  RlsOptions o;
  o.initial_covariance = 1e6;
  const RlsResult r = runRls(H, y, o);
  const LsResult ls = solveLeastSquares(H, y);
  Eigen::MatrixXd A = H.transpose() * H;
  A.diagonal().array() += 1.0 / o.initial_covariance;
  const Eigen::VectorXd ridge = A.ldlt().solve(H.transpose() * y);
  EXPECT_LT((r.x - ridge).norm() / ridge.norm(), 1e-8);
  EXPECT_LT((r.x - ls.x).norm() / ls.x.norm(), 1e-8);
  ASSERT_EQ(r.history.cols(), N);
  EXPECT_TRUE(r.history.col(N - 1) == r.x);
}

TEST(Rls, TwoOutputUpdateEqualsTwoScalarUpdates) {
  // Processing [h1; h2] jointly is algebraically the same as h1 then h2 (lambda = 1); both are
  // computed by the same corrections, so the agreement is to roundoff.
  std::mt19937_64 gen(5);
  std::normal_distribution<double> n01(0.0, 1.0);
  RecursiveLeastSquares a(4, RlsOptions{}), b(4, RlsOptions{});
  for (int k = 0; k < 300; ++k) {
    Eigen::Matrix<double, 2, Eigen::Dynamic> H(2, 4);
    for (int i = 0; i < 8; ++i) H.data()[i] = n01(gen);
    const Eigen::Vector2d y(n01(gen), n01(gen));
    a.update(H, y);
    b.update(H.row(0), y[0]);
    b.update(H.row(1), y[1]);
  }
  EXPECT_LT((a.estimate() - b.estimate()).norm(), 1e-9 * b.estimate().norm());
}

TEST(Rls, ForgettingTracksAParameterChange) {
  // Exponentially weighted LS: n samples after a step of size 3, the old data's weight is at
  // most lambda^n * max(h^2) / min(h^2) = 0.99^1000 * 9 of the total, so |error| <= 27 * 0.99^1000
  // (1.2e-3). Without forgetting the estimate would sit near the average, ~1.5 off.
  RlsOptions o;
  o.forgetting = 0.99;
  RecursiveLeastSquares rls(1, o);
  for (int k = 0; k < 2000; ++k) {
    const double h = 1.0 + 0.5 * std::sin(k);
    rls.update(Eigen::RowVectorXd::Constant(1, h), (k < 1000 ? 2.0 : 5.0) * h);
  }
  EXPECT_NEAR(rls.estimate()[0], 5.0, 27.0 * std::pow(0.99, 1000));
}

TEST(FluctuationRange, MinMaxAfterBurnInWithMargin) {
  Eigen::MatrixXd hist(2, 10);
  for (int k = 0; k < 10; ++k) hist.col(k) << 100.0 * (k == 0) + k, -k;
  FluctuationOptions o;
  o.burn_in_fraction = 0.1;  // drops column 0 (the 100 outlier)
  Box b = fluctuationRange(hist, o);
  EXPECT_EQ(b.lower[0], 1.0);
  EXPECT_EQ(b.upper[0], 9.0);
  EXPECT_EQ(b.lower[1], -9.0);
  EXPECT_EQ(b.upper[1], -1.0);
  o.margin_fraction = 0.5;
  b = fluctuationRange(hist, o);
  EXPECT_EQ(b.lower[0], 1.0 - 4.0);
  EXPECT_EQ(b.upper[0], 9.0 + 4.0);
}

TEST(FluctuationRange, ConstantEstimateGetsMinimumWidth) {
  const Eigen::MatrixXd hist = Eigen::MatrixXd::Constant(1, 5, 2.0);
  const Box b = fluctuationRange(hist, FluctuationOptions{});
  EXPECT_NO_THROW(b.validate());
  EXPECT_TRUE(b.contains(Eigen::VectorXd::Constant(1, 2.0)));
}

TEST(Rls, RejectsBadOptions) {
  RlsOptions o;
  o.forgetting = 0.0;
  EXPECT_THROW(RecursiveLeastSquares(3, o), std::invalid_argument);
  o.forgetting = 1.0;
  o.initial_covariance = -1.0;
  EXPECT_THROW(RecursiveLeastSquares(3, o), std::invalid_argument);
  FluctuationOptions f;
  f.burn_in_fraction = 1.0;
  EXPECT_THROW(fluctuationRange(Eigen::MatrixXd::Ones(2, 4), f), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::ident
