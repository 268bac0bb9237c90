// Least absolute deviations against independent truths: sample medians, brute-force vertex
// enumeration, exact and outlier-corrupted data, and the duality certificate checked by probing.
#include "exoid/ident/estimators/lad.hpp"

#include "lad_test_support.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace exoid::ident {
namespace {

using test::expectInvalidArgumentMentioning;
using test::kEps;
using test::kneeLikeRegressor;
using test::kTol;
using test::l1Cost;
using test::laplace;
using test::roundingLevel;
using test::trueParameters;
using test::uniform;

// The checks every converged result must pass: a valid, tight certificate and a filled summary.
void expectCertified(const LadResult& r, const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  EXPECT_EQ(r.summary.status, Status::kConverged) << r.summary.message;
  // The reported cost is the cost of the reported x (to the rounding of evaluating it).
  EXPECT_NEAR(r.cost, l1Cost(A, b, r.x), roundingLevel(A, b, r.x));
  EXPECT_LE(r.dual_bound, r.cost);
  EXPECT_GE(r.gap, 0.0);
  EXPECT_DOUBLE_EQ(r.gap, r.cost - r.dual_bound);
  EXPECT_LE(r.gap, std::max(kTol * std::max(1.0, r.cost), roundingLevel(A, b, r.x)));
  EXPECT_EQ(r.summary.final_cost, r.cost);
  // The interior point starts at least squares; it only improves on that (up to rounding).
  EXPECT_GE(r.summary.initial_cost, r.cost - roundingLevel(A, b, r.x));
  EXPECT_GE(r.summary.wall_time_s, 0.0);
  EXPECT_FALSE(r.summary.message.empty());
}

TEST(LadTest, OddSampleGivesTheMedian) {
  std::mt19937_64 rng(101);
  const Eigen::Index n = 101;
  Eigen::VectorXd b(n);
  for (auto& v : b) v = uniform(rng, -5.0, 5.0);
  const Eigen::MatrixXd A = Eigen::MatrixXd::Ones(n, 1);
  std::vector<double> sorted(b.data(), b.data() + n);
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[n / 2];

  const LadResult r = solveLeastAbsoluteDeviations(A, b);
  expectCertified(r, A, b);
  // Purification solves 1 * x = b_median: exact up to the 4-ulp slack of EXPECT_DOUBLE_EQ.
  EXPECT_DOUBLE_EQ(r.x[0], median);
  EXPECT_EQ(r.cost, l1Cost(A, b, Eigen::VectorXd::Constant(1, median)));
}

TEST(LadTest, EvenSampleGivesAPointBetweenTheMiddleValues) {
  std::mt19937_64 rng(100);
  const Eigen::Index n = 100;
  Eigen::VectorXd b(n);
  for (auto& v : b) v = uniform(rng, -5.0, 5.0);
  const Eigen::MatrixXd A = Eigen::MatrixXd::Ones(n, 1);
  std::vector<double> sorted(b.data(), b.data() + n);
  std::sort(sorted.begin(), sorted.end());
  const double lo = sorted[n / 2 - 1];
  const double hi = sorted[n / 2];
  // Every point of [lo, hi] is optimal; the minimum is the cost at either end.
  const double optimum = l1Cost(A, b, Eigen::VectorXd::Constant(1, lo));

  const LadResult r = solveLeastAbsoluteDeviations(A, b);
  expectCertified(r, A, b);
  // Slack of one rounding of x (|x| <= 5) on each side.
  EXPECT_GE(r.x[0], lo - 5.0 * kEps);
  EXPECT_LE(r.x[0], hi + 5.0 * kEps);
  // Both are sums of 100 terms each rounded once: they agree to 2 N eps relative.
  EXPECT_NEAR(r.cost, optimum, 2.0 * static_cast<double>(n) * kEps * optimum);
}

// The LAD optimum is attained at a vertex: p rows fitted exactly. Enumerate all C(N, p) of them.
double bruteForceOptimum(const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  const auto n = static_cast<int>(A.rows());
  const auto p = static_cast<int>(A.cols());
  double best = std::numeric_limits<double>::infinity();
  std::vector<int> rows(static_cast<std::size_t>(p));
  std::function<void(int, int)> choose = [&](int first, int k) {
    if (k == p) {
      Eigen::MatrixXd AB(p, p);
      Eigen::VectorXd bB(p);
      for (int i = 0; i < p; ++i) {
        AB.row(i) = A.row(rows[static_cast<std::size_t>(i)]);
        bB[i] = b[rows[static_cast<std::size_t>(i)]];
      }
      const Eigen::FullPivLU<Eigen::MatrixXd> lu(AB);
      if (lu.rank() == p) best = std::min(best, l1Cost(A, b, lu.solve(bB)));
      return;
    }
    for (int i = first; i < n; ++i) {
      rows[static_cast<std::size_t>(k)] = i;
      choose(i + 1, k + 1);
    }
  };
  choose(0, 0);
  return best;
}

TEST(LadTest, MatchesBruteForceVertexEnumeration) {
  std::mt19937_64 rng(8);
  for (int trial = 0; trial < 40; ++trial) {
    const Eigen::Index p = trial % 2 == 0 ? 2 : 3;
    const Eigen::Index n = p == 2 ? 8 : 9;
    Eigen::MatrixXd A(n, p);
    for (auto& v : A.reshaped()) v = uniform(rng, -3.0, 3.0);
    const Eigen::VectorXd x_true = trueParameters(p);
    Eigen::VectorXd b = A * x_true;
    for (auto& v : b) v += laplace(rng, 1.0);
    const double optimum = bruteForceOptimum(A, b);

    const LadResult r = solveLeastAbsoluteDeviations(A, b);
    SCOPED_TRACE("trial " + std::to_string(trial));
    expectCertified(r, A, b);
    // Both land on the same vertex through different p x p solves (a few ulps apart in x);
    // the cost is Lipschitz in x with constant sum_i |a_i|, so 1e-12 relative is ample.
    EXPECT_NEAR(r.cost, optimum, 1e-12 * std::max(1.0, optimum));
    EXPECT_LE(r.dual_bound, optimum + roundingLevel(A, b, r.x));
  }
}

TEST(LadTest, RecoversExactDataExactly) {
  std::mt19937_64 rng(5);
  const Eigen::MatrixXd A = kneeLikeRegressor(500, 5, rng);
  const Eigen::VectorXd x_true = trueParameters(5);
  const Eigen::VectorXd b = A * x_true;

  const LadResult r = solveLeastAbsoluteDeviations(A, b);
  expectCertified(r, A, b);
  // x solves p exact rows; with the scaled condition number ~1e2 its error is ~1e-14 relative.
  EXPECT_LE((r.x - x_true).norm(), 1e-9 * x_true.norm());
  // The cost is then only rounding: far below 1e-10 of ||b||_1.
  EXPECT_LE(r.cost, 1e-10 * b.lpNorm<1>());
}

TEST(LadTest, IgnoresSparseGrossOutliersWhereLeastSquaresCannot) {
  std::mt19937_64 rng(13);
  const Eigen::Index n = 1000;
  const Eigen::MatrixXd A = kneeLikeRegressor(n, 5, rng);
  const Eigen::VectorXd x_true = trueParameters(5);
  Eigen::VectorXd b = A * x_true;
  for (Eigen::Index i = 0; i < n; i += 20) {  // 5 % of the rows carry an error of 50-100
    b[i] += (uniform(rng, -1.0, 1.0) < 0.0 ? -1.0 : 1.0) * uniform(rng, 50.0, 100.0);
  }

  const LadResult r = solveLeastAbsoluteDeviations(A, b);
  expectCertified(r, A, b);
  // LAD's optimum is x_true itself when the clean rows outweigh the outliers in every direction
  // (exact recovery); what is left is the rounding of a p x p solve, as for exact data.
  EXPECT_LE((r.x - x_true).norm(), 1e-9 * x_true.norm());
  // The outliers' share of the cost is exactly their total size.
  EXPECT_NEAR(r.cost, (b - A * x_true).lpNorm<1>(), 1e-9 * r.cost);
  // Least squares spreads the 50 outliers over every parameter: errors of order 1e-2 and more.
  const Eigen::VectorXd x_ls = A.colPivHouseholderQr().solve(b);
  EXPECT_GT((x_ls - x_true).norm(), 1e-3 * x_true.norm());
}

TEST(LadTest, CertificateHoldsAndNoPerturbationDoesBetter) {
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    const Eigen::MatrixXd A = kneeLikeRegressor(2000, 5, rng);
    Eigen::VectorXd b = A * trueParameters(5);
    for (auto& v : b) v += laplace(rng, 0.5);

    const LadResult r = solveLeastAbsoluteDeviations(A, b);
    expectCertified(r, A, b);
    EXPECT_LE(r.gap, kTol * r.cost);
    // Weak duality: every x costs at least dual_bound = cost - gap. Probe that with random
    // perturbations from 1e-9 to 1e-1 of each |x_j|; each cost is evaluated to rounding level.
    const double floor = r.cost - r.gap - 2.0 * roundingLevel(A, b, r.x);
    for (int k = 0; k < 2000; ++k) {
      const double size = std::pow(10.0, uniform(rng, -9.0, -1.0));
      Eigen::VectorXd x = r.x;
      for (auto& v : x) v += size * std::abs(v) * uniform(rng, -1.0, 1.0);
      ASSERT_GE(l1Cost(A, b, x), floor) << "perturbation " << k << " of size " << size;
    }
  }
}

TEST(LadTest, DualVectorReproducesTheBound) {
  std::mt19937_64 rng(12);
  const Eigen::MatrixXd A = kneeLikeRegressor(1000, 5, rng);
  Eigen::VectorXd b = A * trueParameters(5);
  for (auto& v : b) v += laplace(rng, 0.5);
  const LadResult r = solveLeastAbsoluteDeviations(A, b);
  expectCertified(r, A, b);
  // dual_bound = min(cost, b^T u - |x|^T |A^T u|) for the returned u, |u_i| <= 1: recomputed here
  // in long double, it differs from the solver's sums by far less than the cost's rounding.
  ASSERT_EQ(r.dual.size(), b.size());
  EXPECT_LE(r.dual.cwiseAbs().maxCoeff(), 1.0);
  long double bound = 0.0L;
  for (Eigen::Index i = 0; i < b.size(); ++i) bound += static_cast<long double>(b[i]) * r.dual[i];
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    long double g = 0.0L;
    for (Eigen::Index i = 0; i < A.rows(); ++i) g += static_cast<long double>(A(i, j)) * r.dual[i];
    bound -= std::abs(g) * std::abs(static_cast<long double>(r.x[j]));
  }
  EXPECT_NEAR(std::min(static_cast<double>(bound), r.cost), r.dual_bound, roundingLevel(A, b, r.x));

  // Rank deficient: no certificate beyond u = 0.
  Eigen::MatrixXd A_dup = A;
  A_dup.col(3) = A_dup.col(1);
  const LadResult d = solveLeastAbsoluteDeviations(A_dup, b);
  ASSERT_EQ(d.summary.status, Status::kRankDeficient);
  EXPECT_EQ(d.dual, Eigen::VectorXd::Zero(b.size()));
}

TEST(LadTest, ColumnScaleDoesNotChangeTheSolution) {
  std::mt19937_64 rng(21);
  const Eigen::MatrixXd A = kneeLikeRegressor(1500, 5, rng);
  Eigen::VectorXd b = A * trueParameters(5);
  for (auto& v : b) v += laplace(rng, 0.5);
  Eigen::VectorXd scale(5);
  scale << 1e-3, 1e3, 1.0, 1e2, 1e-2;

  const LadResult r = solveLeastAbsoluteDeviations(A, b);
  const LadResult rs = solveLeastAbsoluteDeviations(A * scale.asDiagonal(), b);
  expectCertified(r, A, b);
  expectCertified(rs, A * scale.asDiagonal(), b);
  // Same unique optimal vertex, reached through differently rounded p x p solves.
  EXPECT_LE((scale.cwiseProduct(rs.x) - r.x).norm(), 1e-9 * r.x.norm());
  EXPECT_NEAR(rs.cost, r.cost, 1e-12 * r.cost);
}

TEST(LadTest, ProjectSizedProblemConvergesInFewIterations) {
  std::mt19937_64 rng(20000);
  const Eigen::MatrixXd A = kneeLikeRegressor(20000, 5, rng);
  Eigen::VectorXd b = A * trueParameters(5);
  for (auto& v : b) v += laplace(rng, 0.5);

  const LadResult r = solveLeastAbsoluteDeviations(A, b);
  expectCertified(r, A, b);
  // Measured: ~10 iterations (each one p x p solve); the margin allows other rounding.
  EXPECT_GE(r.summary.iterations, 1);
  EXPECT_LE(r.summary.iterations, 30);
}

TEST(LadTest, IsDeterministic) {
  std::mt19937_64 rng(4);
  const Eigen::MatrixXd A = kneeLikeRegressor(800, 5, rng);
  Eigen::VectorXd b = A * trueParameters(5);
  for (auto& v : b) v += laplace(rng, 0.5);
  const LadResult r1 = solveLeastAbsoluteDeviations(A, b);
  const LadResult r2 = solveLeastAbsoluteDeviations(A, b);
  EXPECT_EQ(r1.x, r2.x);
  EXPECT_EQ(r1.cost, r2.cost);
  EXPECT_EQ(r1.dual_bound, r2.dual_bound);
  EXPECT_EQ(r1.summary.iterations, r2.summary.iterations);
}

TEST(LadTest, ZeroDataGivesZero) {
  std::mt19937_64 rng(0);
  const Eigen::MatrixXd A = kneeLikeRegressor(50, 3, rng);
  const LadResult r = solveLeastAbsoluteDeviations(A, Eigen::VectorXd::Zero(50));
  expectCertified(r, A, Eigen::VectorXd::Zero(50));
  EXPECT_EQ(r.cost, 0.0);
  EXPECT_EQ(r.x, Eigen::VectorXd::Zero(3));
}

TEST(LadTest, IterationLimitReturnsAnHonestCertificate) {
  std::mt19937_64 rng(9);
  const Eigen::MatrixXd A = kneeLikeRegressor(3000, 5, rng);
  Eigen::VectorXd b = A * trueParameters(5);
  for (auto& v : b) v += laplace(rng, 0.5);
  const LadResult full = solveLeastAbsoluteDeviations(A, b);
  ASSERT_EQ(full.summary.status, Status::kConverged);

  LadOptions options;
  options.max_iterations = 1;
  const LadResult r = solveLeastAbsoluteDeviations(A, b, options);
  EXPECT_EQ(r.summary.status, Status::kMaxIterations) << r.summary.message;
  EXPECT_TRUE(usable(r.summary.status));
  EXPECT_EQ(r.summary.iterations, 1);
  EXPECT_EQ(r.cost, l1Cost(A, b, r.x));
  EXPECT_GT(r.gap, kTol * r.cost);
  // Still a valid bracket of the optimum.
  const double slack = 2.0 * roundingLevel(A, b, full.x);
  EXPECT_GE(r.cost, full.cost - slack);
  EXPECT_LE(r.dual_bound, full.cost + slack);
  EXPECT_DOUBLE_EQ(r.gap, r.cost - r.dual_bound);
}

TEST(LadTest, DuplicateColumnIsRankDeficientAndNamed) {
  std::mt19937_64 rng(6);
  Eigen::MatrixXd A = kneeLikeRegressor(400, 5, rng);
  A.col(3) = A.col(1);
  const Eigen::VectorXd b = A * trueParameters(5);
  const LadResult r = solveLeastAbsoluteDeviations(A, b);
  EXPECT_EQ(r.summary.status, Status::kRankDeficient);
  EXPECT_FALSE(usable(r.summary.status));
  const std::string& m = r.summary.message;
  // Pivoting decides which of the two is reported as depending on the other.
  const bool names_pair = m.find("column 3 is a linear combination of column {1}") != std::string::npos ||
                          m.find("column 1 is a linear combination of column {3}") != std::string::npos;
  EXPECT_TRUE(names_pair) << m;
  EXPECT_NE(m.find("rank 4 < 5"), std::string::npos) << m;
  // No estimate, but an honest bracket: x = 0 and the trivially feasible dual u = 0.
  EXPECT_EQ(r.x, Eigen::VectorXd::Zero(5));
  EXPECT_EQ(r.dual_bound, 0.0);
  EXPECT_EQ(r.gap, r.cost);
}

TEST(LadTest, ZeroColumnAndTooFewRowsAreRankDeficient) {
  std::mt19937_64 rng(7);
  Eigen::MatrixXd A = kneeLikeRegressor(100, 4, rng);
  A.col(2).setZero();
  const LadResult r = solveLeastAbsoluteDeviations(A, Eigen::VectorXd::Ones(100));
  EXPECT_EQ(r.summary.status, Status::kRankDeficient);
  EXPECT_NE(r.summary.message.find("column 2 is (numerically) zero"), std::string::npos)
      << r.summary.message;

  const Eigen::MatrixXd wide = kneeLikeRegressor(3, 5, rng);
  const LadResult w = solveLeastAbsoluteDeviations(wide, Eigen::VectorXd::Ones(3));
  EXPECT_EQ(w.summary.status, Status::kRankDeficient);
  EXPECT_NE(w.summary.message.find("rank 3 < 5"), std::string::npos) << w.summary.message;
}

TEST(LadTest, RejectsBadInput) {
  std::mt19937_64 rng(3);
  const Eigen::MatrixXd A = kneeLikeRegressor(20, 3, rng);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(20);
  expectInvalidArgumentMentioning([&] { solveLeastAbsoluteDeviations(A, Eigen::VectorXd::Ones(19)); },
                "expected b of size 20 (the rows of A), got 19");
  expectInvalidArgumentMentioning([&] { solveLeastAbsoluteDeviations(Eigen::MatrixXd(0, 3), Eigen::VectorXd(0)); },
                "A must have at least one row and one column, got 0 x 3");
  Eigen::MatrixXd A_nan = A;
  A_nan(4, 2) = std::numeric_limits<double>::quiet_NaN();
  expectInvalidArgumentMentioning([&] { solveLeastAbsoluteDeviations(A_nan, b); }, "A(4, 2) is not finite, got nan");
  Eigen::VectorXd b_inf = b;
  b_inf[7] = std::numeric_limits<double>::infinity();
  expectInvalidArgumentMentioning([&] { solveLeastAbsoluteDeviations(A, b_inf); }, "b(7) is not finite, got inf");

  LadOptions options;
  options.gap_tolerance = 2.0;
  expectInvalidArgumentMentioning([&] { options.validate(); }, "'gap_tolerance' must be in (0, 1), got 2");
  expectInvalidArgumentMentioning([&] { solveLeastAbsoluteDeviations(A, b, options); }, "'gap_tolerance'");
  options.gap_tolerance = 0.0;
  expectInvalidArgumentMentioning([&] { options.validate(); }, "'gap_tolerance' must be in (0, 1), got 0");
  options.gap_tolerance = std::numeric_limits<double>::quiet_NaN();
  expectInvalidArgumentMentioning([&] { options.validate(); }, "'gap_tolerance' must be in (0, 1), got nan");
  options = LadOptions{};
  options.max_iterations = 0;
  expectInvalidArgumentMentioning([&] { options.validate(); }, "'max_iterations' must be >= 1, got 0");
  EXPECT_NO_THROW(LadOptions{}.validate());
}

}  // namespace
}  // namespace exoid::ident
