// Box-constrained least absolute deviations against independent truths: the unconstrained
// optimum when the box holds it, brute-force enumeration of the vertices made of data rows and
// box faces (in long double), the clamped median, reduced problems with the active bounds fixed,
// random feasible probes, and every certificate re-derived here from the returned dual vector.
#include "exoid/ident/estimators/lad_box.hpp"

#include "lad_test_support.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>

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

using MatrixL = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
using VectorL = Eigen::Matrix<long double, Eigen::Dynamic, 1>;

// The largest rounding level of any point of the box (|x_j| <= max(|lower_j|, |upper_j|)).
double boxRoundingLevel(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Box& box) {
  return roundingLevel(A, b, box.lower.cwiseAbs().cwiseMax(box.upper.cwiseAbs()));
}

// b = A x_true + Laplace(0.5) noise, x_true = (0.3, 1.0, 1.7, ...).
Eigen::VectorXd noisyData(const Eigen::MatrixXd& A, std::mt19937_64& rng) {
  Eigen::VectorXd b = A * trueParameters(A.cols());
  for (auto& v : b) v += laplace(rng, 0.5);
  return b;
}

// The certificate re-derived from the returned dual: for |u_i| <= 1 and every x in the box,
// ||b - A x||_1 >= b^T u - sum_j max(lower_j g_j, upper_j g_j), g = A^T u (weak duality), so a
// bound this function computes is a valid lower bound whatever the solver did. Long double sums.
double boxBound(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Box& box,
                const Eigen::VectorXd& u) {
  long double bound = 0.0L;
  for (Eigen::Index i = 0; i < b.size(); ++i) bound += static_cast<long double>(b[i]) * u[i];
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    long double g = 0.0L;
    for (Eigen::Index i = 0; i < A.rows(); ++i) g += static_cast<long double>(A(i, j)) * u[i];
    bound -= std::max(box.lower[j] * g, box.upper[j] * g);
  }
  return static_cast<double>(bound);
}

// The checks every converged result must pass: a feasible x, its cost, a certificate that holds
// when re-derived here from the dual vector, the active-bound report, and a filled summary.
void expectCertified(const BoxedLadResult& r, const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                     const Box& box) {
  EXPECT_EQ(r.summary.status, Status::kConverged) << r.summary.message;
  ASSERT_EQ(r.x.size(), A.cols());
  EXPECT_TRUE(box.contains(r.x));
  const double rounding = roundingLevel(A, b, r.x);
  EXPECT_NEAR(r.cost, l1Cost(A, b, r.x), rounding);
  // The dual is what the bound claims to be built from: |u_i| <= 1 and its bound >= dual_bound
  // (the long double sums differ from the solver's by far less than the cost's rounding).
  ASSERT_EQ(r.dual.size(), A.rows());
  EXPECT_LE(r.dual.cwiseAbs().maxCoeff(), 1.0);
  EXPECT_GE(boxBound(A, b, box, r.dual), r.dual_bound - rounding);
  EXPECT_LE(r.dual_bound, r.cost);
  EXPECT_GE(r.gap, 0.0);
  EXPECT_DOUBLE_EQ(r.gap, r.cost - r.dual_bound);
  EXPECT_LE(r.gap, std::max(kTol * std::max(1.0, r.cost), rounding));
  // at_bound says which bound x_j equals, and activeBounds() counts them.
  ASSERT_EQ(r.at_bound.size(), static_cast<std::size_t>(A.cols()));
  int active = 0;
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    const int expected = r.x[j] == box.lower[j] ? -1 : r.x[j] == box.upper[j] ? 1 : 0;
    EXPECT_EQ(r.at_bound[static_cast<std::size_t>(j)], expected) << "parameter " << j;
    active += expected != 0;
  }
  EXPECT_EQ(r.activeBounds(), active);
  EXPECT_EQ(r.summary.final_cost, r.cost);
  // initial_cost is the cost at the box centre, a feasible point: never below the optimum, hence
  // never below the bound (up to the rounding of evaluating it there).
  const Eigen::VectorXd centre = 0.5 * (box.lower + box.upper);
  EXPECT_GE(r.summary.initial_cost, r.dual_bound - roundingLevel(A, b, centre));
  EXPECT_GE(r.summary.wall_time_s, 0.0);
  EXPECT_FALSE(r.summary.message.empty());
}

TEST(LadBoxTest, BoxHoldingTheUnconstrainedOptimumReturnsIt) {
  std::mt19937_64 rng(31);
  const Eigen::MatrixXd A = kneeLikeRegressor(2000, 5, rng);
  const Eigen::VectorXd b = noisyData(A, rng);
  const LadResult free = solveLeastAbsoluteDeviations(A, b);
  ASSERT_EQ(free.summary.status, Status::kConverged);
  const Box box{free.x.array() - 0.5 * free.x.array().abs() - 0.1,
                free.x.array() + 0.5 * free.x.array().abs() + 0.1};

  const BoxedLadResult r = solveBoxedLeastAbsoluteDeviations(A, b, box);
  expectCertified(r, A, b, box);
  // Both certificates bracket the same optimum, so the costs differ by at most the larger gap
  // plus the rounding of each cost.
  const double rounding = roundingLevel(A, b, free.x);
  EXPECT_NEAR(r.cost, free.cost, std::max(r.gap, free.gap) + 2.0 * rounding);
  // The same unique vertex, reached through differently rounded p x p solves (as in lad_test).
  EXPECT_LE((r.x - free.x).norm(), 1e-9 * free.x.norm());
  EXPECT_EQ(r.activeBounds(), 0);
}

TEST(LadBoxTest, ParameterHeldJustInsideABoundIsNotFlagged) {
  // A box of width ~1e6 whose lower bounds sit 1e-4 below the unconstrained optimum: closer than
  // the 1e-9-of-the-width distance at which the solver tries a bound (1e-3), but moving onto it
  // raises the cost by ~1e-4 times the cost's slope, far above its rounding. The box holds the
  // optimum, so the answer is the unconstrained one, strictly inside.
  std::mt19937_64 rng(32);
  const Eigen::MatrixXd A = kneeLikeRegressor(2000, 5, rng);
  const Eigen::VectorXd b = noisyData(A, rng);
  const LadResult free = solveLeastAbsoluteDeviations(A, b);
  ASSERT_EQ(free.summary.status, Status::kConverged);
  const Box box{free.x.array() - 1e-4, Eigen::VectorXd::Constant(5, 1e6)};

  const BoxedLadResult r = solveBoxedLeastAbsoluteDeviations(A, b, box);
  expectCertified(r, A, b, box);
  EXPECT_NEAR(r.cost, free.cost, std::max(r.gap, free.gap) + 2.0 * roundingLevel(A, b, free.x));
  EXPECT_EQ(r.at_bound, std::vector<int>(5, 0));
  EXPECT_LE((r.x - free.x).norm(), 1e-9 * free.x.norm());
}

// The box optimum is attained at a vertex: p linearly independent active constraints among the
// data rows (zero residual) and the faces x_j = lower_j, x_j = upper_j. Enumerate every p-subset
// in long double: faces fix their coordinates exactly, the chosen rows determine the rest, and
// only points inside the box count. A point exactly on a face that rounding puts just outside is
// enumerated again with that face in its subset; a feasible point's cost can never undercut the
// optimum, so the minimum is the optimum to long double precision.
double bruteForceBoxOptimum(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Box& box) {
  const auto n = static_cast<int>(A.rows());
  const auto p = static_cast<int>(A.cols());
  const MatrixL AL = A.cast<long double>();
  const VectorL bL = b.cast<long double>();
  long double best = std::numeric_limits<long double>::infinity();
  std::vector<int> chosen(static_cast<std::size_t>(p));  // < n: a row; n + 2j (+1): lower (upper) j
  const auto evaluate = [&]() {
    VectorL x = VectorL::Zero(p);
    std::vector<bool> fixed(static_cast<std::size_t>(p), false);
    std::vector<int> rows;
    for (const int c : chosen) {
      if (c < n) {
        rows.push_back(c);
        continue;
      }
      const int j = (c - n) / 2;
      if (fixed[static_cast<std::size_t>(j)]) return;  // both faces of one coordinate
      fixed[static_cast<std::size_t>(j)] = true;
      x[j] = (c - n) % 2 == 0 ? box.lower[j] : box.upper[j];
    }
    std::vector<int> free;
    for (int j = 0; j < p; ++j) {
      if (!fixed[static_cast<std::size_t>(j)]) free.push_back(j);
    }
    const auto k = static_cast<Eigen::Index>(rows.size());  // == free.size()
    if (k > 0) {
      MatrixL M(k, k);
      VectorL rhs(k);
      for (Eigen::Index r = 0; r < k; ++r) {
        const int i = rows[static_cast<std::size_t>(r)];
        rhs[r] = bL[i] - AL.row(i).dot(x);
        for (Eigen::Index f = 0; f < k; ++f) M(r, f) = AL(i, free[static_cast<std::size_t>(f)]);
      }
      const Eigen::FullPivLU<MatrixL> lu(M);
      if (lu.rank() < k) return;
      const VectorL y = lu.solve(rhs);
      for (Eigen::Index f = 0; f < k; ++f) x[free[static_cast<std::size_t>(f)]] = y[f];
    }
    for (int j = 0; j < p; ++j) {
      if (x[j] < box.lower[j] || x[j] > box.upper[j]) return;
    }
    best = std::min(best, (bL - AL * x).cwiseAbs().sum());
  };
  std::function<void(int, int)> choose = [&](int first, int depth) {
    if (depth == p) {
      evaluate();
      return;
    }
    for (int c = first; c < n + 2 * p; ++c) {
      chosen[static_cast<std::size_t>(depth)] = c;
      choose(c + 1, depth + 1);
    }
  };
  choose(0, 0);
  return static_cast<double>(best);
}

// A box that cuts the unconstrained optimum x_free off in at least one coordinate: each
// coordinate's box either holds x_free[j] or lies wholly above or below it.
Box cuttingBox(const Eigen::VectorXd& x_free, std::mt19937_64& rng) {
  const Eigen::Index p = x_free.size();
  Box box{Eigen::VectorXd(p), Eigen::VectorXd(p)};
  const auto first_cut = static_cast<Eigen::Index>(rng() % static_cast<std::uint64_t>(p));
  for (Eigen::Index j = 0; j < p; ++j) {
    const double s = std::abs(x_free[j]) + 0.5;
    const auto kind = j == first_cut ? 1 + rng() % 2 : rng() % 3;
    if (kind == 0) {
      box.lower[j] = x_free[j] - uniform(rng, 0.5, 2.0) * s;
      box.upper[j] = x_free[j] + uniform(rng, 0.5, 2.0) * s;
    } else if (kind == 1) {  // below x_free[j]
      box.upper[j] = x_free[j] - uniform(rng, 0.1, 1.0) * s;
      box.lower[j] = box.upper[j] - uniform(rng, 0.5, 2.0) * s;
    } else {  // above x_free[j]
      box.lower[j] = x_free[j] + uniform(rng, 0.1, 1.0) * s;
      box.upper[j] = box.lower[j] + uniform(rng, 0.5, 2.0) * s;
    }
  }
  return box;
}

// cost >= optimum - rounding (x is feasible; its cost is evaluated to rounding level) and
// cost = dual_bound + gap <= optimum + gap (+ rounding), gap <= max(1e-10 max(1, cost), rounding)
// by expectCertified; the bound itself never exceeds the optimum.
void expectMatchesOptimum(const BoxedLadResult& r, const Eigen::MatrixXd& A,
                          const Eigen::VectorXd& b, double optimum) {
  const double rounding = roundingLevel(A, b, r.x);
  EXPECT_GE(r.cost, optimum - rounding);
  EXPECT_LE(r.cost, optimum + r.gap + rounding);
  EXPECT_LE(r.dual_bound, optimum + rounding);
}

TEST(LadBoxTest, MatchesBruteForceVertexEnumerationWithBoxFaces) {
  std::mt19937_64 rng(17);
  for (int trial = 0; trial < 36; ++trial) {
    const Eigen::Index p = 2 + trial % 3;
    const Eigen::Index n = 8 + trial % 8;
    Eigen::MatrixXd A(n, p);
    for (auto& v : A.reshaped()) v = uniform(rng, -3.0, 3.0);
    Eigen::VectorXd b = A * Eigen::VectorXd::LinSpaced(p, 0.3, 2.0);
    for (auto& v : b) v += laplace(rng, 1.0);
    // The unconstrained optimum only places the box; the truth is the enumeration.
    const LadResult free = solveLeastAbsoluteDeviations(A, b);
    ASSERT_EQ(free.summary.status, Status::kConverged);
    const Box box = cuttingBox(free.x, rng);
    ASSERT_FALSE(box.contains(free.x));
    const double optimum = bruteForceBoxOptimum(A, b, box);

    const BoxedLadResult r = solveBoxedLeastAbsoluteDeviations(A, b, box);
    SCOPED_TRACE("trial " + std::to_string(trial) + ", p = " + std::to_string(p) +
                 ", n = " + std::to_string(n));
    expectCertified(r, A, b, box);
    expectMatchesOptimum(r, A, b, optimum);
    // Cutting the unconstrained optimum off costs something (it is unique for random data).
    EXPECT_GT(optimum, free.cost);
  }
}

TEST(LadBoxTest, OneDimensionalOptimumIsTheMedianClampedIntoTheInterval) {
  std::mt19937_64 rng(101);
  const Eigen::Index n = 101;
  Eigen::VectorXd b(n);
  for (auto& v : b) v = uniform(rng, -5.0, 5.0);
  const Eigen::MatrixXd A = Eigen::MatrixXd::Ones(n, 1);
  std::vector<double> sorted(b.data(), b.data() + n);
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[n / 2];

  struct Case {
    double lo, hi;
    int side;
  };
  for (const Case c : {Case{median - 1.0, median + 2.0, 0}, Case{median + 0.5, median + 3.0, -1},
                       Case{median - 4.0, median - 0.25, 1}, Case{-100.0, sorted[10], 1}}) {
    SCOPED_TRACE("interval [" + std::to_string(c.lo) + ", " + std::to_string(c.hi) + "]");
    const Box box{Eigen::VectorXd::Constant(1, c.lo), Eigen::VectorXd::Constant(1, c.hi)};
    const BoxedLadResult r = solveBoxedLeastAbsoluteDeviations(A, b, box);
    expectCertified(r, A, b, box);
    // The minimiser of sum |b_i - x| over [lo, hi] is the median clamped into it: a bound exactly
    // (x is put on it), the median itself up to the 4-ulp slack of EXPECT_DOUBLE_EQ.
    const double expected = std::clamp(median, c.lo, c.hi);
    EXPECT_DOUBLE_EQ(r.x[0], expected);
    if (c.side != 0) {
      EXPECT_EQ(r.x[0], expected);
    }
    EXPECT_EQ(r.at_bound, std::vector<int>{c.side});
    // 4 ulps of x move each of the n terms by at most 4 eps |x|, plus each term's rounding.
    const Eigen::VectorXd x_expected = Eigen::VectorXd::Constant(1, expected);
    EXPECT_NEAR(r.cost, l1Cost(A, b, x_expected),
                4.0 * static_cast<double>(n) * kEps * std::abs(expected) +
                    roundingLevel(A, b, x_expected));
  }
}

TEST(LadBoxTest, KneeLikeProblemWithBoundsForcedActive) {
  std::mt19937_64 rng(10000);
  const Eigen::MatrixXd A = kneeLikeRegressor(10000, 5, rng);
  const Eigen::VectorXd b = noisyData(A, rng);
  const LadResult free = solveLeastAbsoluteDeviations(A, b);
  ASSERT_EQ(free.summary.status, Status::kConverged);
  // A box of +-1 around the unconstrained optimum, cut below it in x0 and above it in x3.
  Box box{free.x.array() - 1.0, free.x.array() + 1.0};
  box.upper[0] = free.x[0] - 0.05;
  box.lower[3] = free.x[3] + 0.2;

  const BoxedLadResult r = solveBoxedLeastAbsoluteDeviations(A, b, box);
  expectCertified(r, A, b, box);
  RecordProperty("boxed_wall_time_ms", std::to_string(1e3 * r.summary.wall_time_s));
  // Measured: 14 interior-point iterations, one pass (the plain solver takes ~11 on such data).
  EXPECT_LE(r.summary.iterations, 40);

  // Independent truth: with x0 = upper_0 and x3 = lower_3 fixed, the unconstrained optimum of the
  // other three lies strictly inside the box, so it is a feasible point; the certificate above
  // (re-derived from the dual) says no box point costs less. So the box optimum sits on exactly
  // those two bounds, and it is unique here (random noise), so it is that point.
  const std::vector<Eigen::Index> free_cols = {1, 2, 4};
  Eigen::VectorXd x_face = box.lower;
  x_face[0] = box.upper[0];
  const Eigen::VectorXd b_face = b - A.col(0) * x_face[0] - A.col(3) * x_face[3];
  const LadResult face = solveLeastAbsoluteDeviations(A(Eigen::all, free_cols), b_face);
  ASSERT_EQ(face.summary.status, Status::kConverged);
  for (std::size_t k = 0; k < free_cols.size(); ++k) {
    const Eigen::Index j = free_cols[k];
    x_face[j] = face.x[static_cast<Eigen::Index>(k)];
    EXPECT_GT(x_face[j], box.lower[j] + 1e-3) << "parameter " << j;
    EXPECT_LT(x_face[j], box.upper[j] - 1e-3) << "parameter " << j;
  }
  const double rounding = roundingLevel(A, b, x_face);
  expectMatchesOptimum(r, A, b, l1Cost(A, b, x_face));
  EXPECT_LE(r.dual_bound, l1Cost(A, b, x_face) + rounding);
  EXPECT_EQ(r.at_bound, (std::vector<int>{1, 0, 0, -1, 0}));
  EXPECT_EQ(r.x[0], box.upper[0]);
  EXPECT_EQ(r.x[3], box.lower[3]);
  // Same vertex through differently rounded solves (as in lad_test).
  EXPECT_LE((r.x - x_face).norm(), 1e-9 * x_face.norm());

  // No feasible point does better than the bound: uniform over the box and clamped
  // perturbations of x from 1e-9 to 1e-1 of the width; each cost is evaluated to rounding level.
  const double floor = r.dual_bound - 2.0 * boxRoundingLevel(A, b, box);
  const Eigen::VectorXd width = box.upper - box.lower;
  for (int k = 0; k < 2000; ++k) {
    Eigen::VectorXd x(5);
    if (k % 2 == 0) {
      for (Eigen::Index j = 0; j < 5; ++j) x[j] = uniform(rng, box.lower[j], box.upper[j]);
    } else {
      const double size = std::pow(10.0, uniform(rng, -9.0, -1.0));
      for (Eigen::Index j = 0; j < 5; ++j) {
        x[j] = r.x[j] + size * width[j] * uniform(rng, -1.0, 1.0);
      }
      x = x.cwiseMax(box.lower).cwiseMin(box.upper);
    }
    ASSERT_GE(l1Cost(A, b, x), floor) << "probe " << k;
  }
}

TEST(LadBoxTest, RankDeficientDataIsWellPosedInABox) {
  // Small: a duplicated column, against the enumeration (which needs a face for every vertex).
  std::mt19937_64 rng(55);
  for (int trial = 0; trial < 12; ++trial) {
    const Eigen::Index p = 3;
    const Eigen::Index n = 10 + trial % 4;
    Eigen::MatrixXd A(n, p);
    for (auto& v : A.reshaped()) v = uniform(rng, -3.0, 3.0);
    A.col(2) = A.col(0);
    Eigen::VectorXd b = A * Eigen::Vector3d(0.5, 1.0, 1.5);
    for (auto& v : b) v += laplace(rng, 1.0);
    ASSERT_EQ(solveLeastAbsoluteDeviations(A, b).summary.status, Status::kRankDeficient);
    Box box{Eigen::VectorXd(p), Eigen::VectorXd(p)};
    for (Eigen::Index j = 0; j < p; ++j) {
      box.lower[j] = uniform(rng, -1.0, 1.0);
      box.upper[j] = box.lower[j] + uniform(rng, 0.5, 3.0);
    }
    const double optimum = bruteForceBoxOptimum(A, b, box);

    const BoxedLadResult r = solveBoxedLeastAbsoluteDeviations(A, b, box);
    SCOPED_TRACE("trial " + std::to_string(trial));
    expectCertified(r, A, b, box);
    expectMatchesOptimum(r, A, b, optimum);
  }

  // Project-sized: a duplicated and a zero column. x_1 + x_3 is all the data sees and x_2 is
  // invisible to it, so x is not unique; the cost and its certificate are.
  std::mt19937_64 rng_knee(56);
  Eigen::MatrixXd A = kneeLikeRegressor(3000, 5, rng_knee);
  const Eigen::VectorXd b = noisyData(A, rng_knee);
  A.col(3) = A.col(1);
  A.col(2).setZero();
  const Box box = Box::uniform(5, -3.0, 3.0);
  const BoxedLadResult r = solveBoxedLeastAbsoluteDeviations(A, b, box);
  expectCertified(r, A, b, box);
}

TEST(LadBoxTest, BoxesFarWiderThanTheSolutionStillCertify) {
  // Bounds of 1e6 put rounding errors of ~eps c_j 1e6 into the penalty rows, far above the data
  // cost's resolution: the second pass (active bounds fixed, dual refined) must deliver.
  std::mt19937_64 rng(77);
  const Eigen::MatrixXd A = kneeLikeRegressor(5000, 5, rng);
  const Eigen::VectorXd b = noisyData(A, rng);
  const LadResult free = solveLeastAbsoluteDeviations(A, b);
  ASSERT_EQ(free.summary.status, Status::kConverged);

  const Box wide = Box::uniform(5, -1e6, 1e6);
  const BoxedLadResult r = solveBoxedLeastAbsoluteDeviations(A, b, wide);
  expectCertified(r, A, b, wide);
  EXPECT_NEAR(r.cost, free.cost, std::max(r.gap, free.gap) + 2.0 * roundingLevel(A, b, free.x));
  EXPECT_EQ(r.activeBounds(), 0);

  // The same with two bounds active (upper = 2 lies below x3 ~ 2.4 and x4 ~ 3.1).
  const Box lopsided = Box::uniform(5, -1e6, 2.0);
  ASSERT_FALSE(lopsided.contains(free.x));
  const BoxedLadResult s = solveBoxedLeastAbsoluteDeviations(A, b, lopsided);
  expectCertified(s, A, b, lopsided);
  EXPECT_EQ(s.at_bound, (std::vector<int>{0, 0, 0, 1, 1}));
}

TEST(LadBoxTest, IterationLimitReturnsAnHonestBracket) {
  std::mt19937_64 rng(9);
  const Eigen::MatrixXd A = kneeLikeRegressor(3000, 5, rng);
  const Eigen::VectorXd b = noisyData(A, rng);
  Box box = Box::uniform(5, -5.0, 5.0);
  box.upper[0] = 0.1;
  const BoxedLadResult full = solveBoxedLeastAbsoluteDeviations(A, b, box);
  ASSERT_EQ(full.summary.status, Status::kConverged);

  LadOptions options;
  options.max_iterations = 1;
  const BoxedLadResult r = solveBoxedLeastAbsoluteDeviations(A, b, box, options);
  EXPECT_TRUE(usable(r.summary.status)) << r.summary.message;
  EXPECT_TRUE(box.contains(r.x));
  EXPECT_EQ(r.cost, l1Cost(A, b, r.x));
  EXPECT_DOUBLE_EQ(r.gap, r.cost - r.dual_bound);
  EXPECT_GE(boxBound(A, b, box, r.dual), r.dual_bound - roundingLevel(A, b, r.x));
  // A bracket of the optimum whatever the status.
  const double slack = 2.0 * boxRoundingLevel(A, b, box);
  EXPECT_GE(r.cost, full.cost - slack);
  EXPECT_LE(r.dual_bound, full.cost + slack);
}

TEST(LadBoxTest, RejectsBadInput) {
  std::mt19937_64 rng(3);
  const Eigen::MatrixXd A = kneeLikeRegressor(20, 5, rng).leftCols(3);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(20);
  const Box box = Box::uniform(3, -1.0, 1.0);
  const auto solve = [](const Eigen::MatrixXd& A_, const Eigen::VectorXd& b_, const Box& box_) {
    return [=] { solveBoxedLeastAbsoluteDeviations(A_, b_, box_); };
  };
  expectInvalidArgumentMentioning(solve(A, Eigen::VectorXd::Ones(19), box),
                "expected b of size 20 (the rows of A), got 19");
  expectInvalidArgumentMentioning(solve(Eigen::MatrixXd(0, 3), Eigen::VectorXd(0), box),
                "A must have at least one row and one column, got 0 x 3");
  expectInvalidArgumentMentioning(solve(A, b, Box::uniform(2, -1.0, 1.0)),
                "expected a box of dimension 3 (the columns of A), got lower of size 2 and upper "
                "of size 2");
  expectInvalidArgumentMentioning(solve(A, b, Box{Eigen::VectorXd::Zero(3), Eigen::VectorXd::Ones(4)}),
                "got lower of size 3 and upper of size 4");
  Box flat = box;
  flat.lower[1] = 2.0;
  flat.upper[1] = 2.0;
  expectInvalidArgumentMentioning(solve(A, b, flat), "box.lower(1) = 2 must be < box.upper(1) = 2");
  Box inverted = box;
  inverted.lower[2] = 0.5;
  inverted.upper[2] = -0.5;
  expectInvalidArgumentMentioning(solve(A, b, inverted), "box.lower(2) = 0.5 must be < box.upper(2) = -0.5");
  Box nan_box = box;
  nan_box.upper[0] = std::numeric_limits<double>::quiet_NaN();
  expectInvalidArgumentMentioning(solve(A, b, nan_box), "box.upper(0) is not finite, got nan");
  Box inf_box = box;
  inf_box.lower[2] = -std::numeric_limits<double>::infinity();
  expectInvalidArgumentMentioning(solve(A, b, inf_box), "box.lower(2) is not finite, got -inf");
  Eigen::MatrixXd A_nan = A;
  A_nan(4, 2) = std::numeric_limits<double>::quiet_NaN();
  expectInvalidArgumentMentioning(solve(A_nan, b, box), "A(4, 2) is not finite, got nan");
  Eigen::VectorXd b_inf = b;
  b_inf[7] = std::numeric_limits<double>::infinity();
  expectInvalidArgumentMentioning(solve(A, b_inf, box), "b(7) is not finite, got inf");
  LadOptions options;
  options.gap_tolerance = 2.0;
  expectInvalidArgumentMentioning([&] { solveBoxedLeastAbsoluteDeviations(A, b, box, options); },
                "'gap_tolerance' must be in (0, 1), got 2");
}

}  // namespace
}  // namespace exoid::ident
