// Nelder-Mead against problems with known minima.
#include "exoid/ident/estimators/nelder_mead.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace exoid::ident {
namespace {

TEST(NelderMead, FindsTheRosenbrockMinimum) {
  // f = (1 - x)^2 + 100 (y - x^2)^2, minimum 0 at (1, 1), the classic start (-1.2, 1).
  const auto f = [](const Eigen::VectorXd& v) { return std::pow(1 - v[0], 2) + 100 * std::pow(v[1] - v[0] * v[0], 2); };
  NelderMeadOptions o;
  o.max_evaluations = 5000;
  const NelderMeadResult r = minimizeNelderMead(f, Eigen::Vector2d(-1.2, 1.0), o);
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.x[0], 1.0, 1e-4);
  EXPECT_NEAR(r.x[1], 1.0, 1e-4);
  EXPECT_LT(r.f, 1e-8);
}

TEST(NelderMead, FindsTheMinimumOfAnIllScaledQuadraticIn10D) {
  // f = sum_i 10^(i/3) (x_i - i)^2: condition 1000, minimum at x_i = i.
  const auto f = [](const Eigen::VectorXd& v) {
    double s = 0.0;
    for (Eigen::Index i = 0; i < v.size(); ++i) s += std::pow(10.0, double(i) / 3.0) * std::pow(v[i] - double(i), 2);
    return s;
  };
  NelderMeadOptions o;
  o.max_evaluations = 200000;
  o.initial_step = 1.0;
  const NelderMeadResult r = minimizeNelderMead(f, Eigen::VectorXd::Zero(10), o);
  EXPECT_TRUE(r.converged);
  for (Eigen::Index i = 0; i < 10; ++i) EXPECT_NEAR(r.x[i], double(i), 1e-3) << i;
}

TEST(NelderMead, TreatsNonFiniteValuesAsInfinityAndIsDeterministic) {
  // NaN outside x > 0: the minimum of (x - 2)^2 there is still found.
  const auto f = [](const Eigen::VectorXd& v) {
    return v[0] > 0 ? (v[0] - 2) * (v[0] - 2) + v[1] * v[1] : std::numeric_limits<double>::quiet_NaN();
  };
  const NelderMeadResult a = minimizeNelderMead(f, Eigen::Vector2d(0.5, 0.3));
  const NelderMeadResult b = minimizeNelderMead(f, Eigen::Vector2d(0.5, 0.3));
  EXPECT_NEAR(a.x[0], 2.0, 1e-4);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.evaluations, b.evaluations);
  test::expectInvalidArgumentMentioning([&] { NelderMeadOptions o; o.initial_step = 0; minimizeNelderMead(f, Eigen::Vector2d(1, 1), o); }, "initial_step");
}

}  // namespace
}  // namespace exoid::ident
