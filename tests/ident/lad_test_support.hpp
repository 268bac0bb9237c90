#pragma once
// Test-only helpers shared by lad_test.cpp and lad_box_test.cpp: the L1 cost and its rounding
// level computed independently of the solvers, the random draws, the knee-like regressor, and
// the check for rejected input.
#include "exoid/ident/estimators/lad.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <Eigen/Core>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

namespace exoid::test {

inline constexpr double kEps = std::numeric_limits<double>::epsilon();
inline constexpr double kTol = ident::LadOptions{}.gap_tolerance;  // 1e-10

// sum_i |b_i - a_i^T x|, accumulated in long double so the test's own sum adds no error.
inline double l1Cost(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& x) {
  const Eigen::VectorXd r = b - A * x;
  long double sum = 0.0L;
  for (Eigen::Index i = 0; i < r.size(); ++i) sum += std::abs(static_cast<long double>(r[i]));
  return static_cast<double>(sum);
}

// Error bound of evaluating b - A x in double, summed over the rows: two evaluations of the cost
// at the same or nearby points cannot be compared more finely than this.
inline double roundingLevel(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                            const Eigen::VectorXd& x) {
  const double abs_ax = A.cwiseAbs().colwise().sum().dot(x.cwiseAbs().transpose());
  return static_cast<double>(A.cols() + 1) * kEps * (b.lpNorm<1>() + abs_ax);
}

inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// Laplace(0, scale) by inverting its CDF.
inline double laplace(std::mt19937_64& rng, double scale) {
  const double u = uniform(rng, -0.5, 0.5);
  return -scale * (u < 0.0 ? -1.0 : 1.0) * std::log1p(-2.0 * std::abs(u));
}

// A knee-like regressor sampled at 1 kHz: columns of very different size as in the paper's
// equation, qdd (~30), g sin q (~10), g cos q (~10), sgn(qd) (1), qd (~3), then random columns.
// Draws from rng: the phase, then row by row the random columns (none for p <= 5), so the tests'
// later draws, and hence their numbers, depend on this order.
inline Eigen::MatrixXd kneeLikeRegressor(Eigen::Index n, Eigen::Index p, std::mt19937_64& rng) {
  constexpr double kTwoPi = 6.283185307179586;
  const double phase = uniform(rng, 0.0, kTwoPi);
  Eigen::MatrixXd A(n, p);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = 1e-3 * static_cast<double>(i);
    const double w1 = kTwoPi * 0.5, w2 = kTwoPi * 1.3;
    const double q = 0.8 * std::sin(w1 * t) + 0.3 * std::sin(w2 * t + phase);
    const double qd = 0.8 * w1 * std::cos(w1 * t) + 0.3 * w2 * std::cos(w2 * t + phase);
    const double qdd = -0.8 * w1 * w1 * std::sin(w1 * t) - 0.3 * w2 * w2 * std::sin(w2 * t + phase);
    const double cols[5] = {qdd, 9.81 * std::sin(q), 9.81 * std::cos(q), qd > 0.0 ? 1.0 : -1.0, qd};
    for (Eigen::Index j = 0; j < p; ++j) A(i, j) = j < 5 ? cols[j] : uniform(rng, -2.0, 2.0);
  }
  return A;
}

// x_true = (0.3, 1.0, 1.7, ...): the parameters the tests' data are generated from.
inline Eigen::VectorXd trueParameters(Eigen::Index p) {
  Eigen::VectorXd x(p);
  for (Eigen::Index j = 0; j < p; ++j) x[j] = 0.3 + 0.7 * static_cast<double>(j);
  return x;
}


}  // namespace exoid::test
