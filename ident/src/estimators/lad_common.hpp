#pragma once
// Pieces both LAD solvers (lad.cpp, lad_box.cpp) use: the L1 cost in long double, the rounding
// level below which no two costs can be told apart, and input checks with their messages.
#include "exoid/core/format.hpp"

#include <Eigen/Core>

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace exoid::ident::lad_detail {

/// ||b - A x||_1 accumulated in long double.
inline double l1Cost(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& x) {
  const Eigen::VectorXd r = b - A * x;
  long double sum = 0.0L;
  for (Eigen::Index i = 0; i < r.size(); ++i) sum += std::abs(static_cast<long double>(r[i]));
  return static_cast<double>(sum);
}

/// The rounding error bound of evaluating b - A x in double, summed over rows:
/// (p + 1) eps sum_i (|b_i| + |a_i|^T |x|). No cost, hence no gap, is resolved more finely.
inline double roundingLevel(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& x) {
  const double abs_ax = A.cwiseAbs().colwise().sum().dot(x.cwiseAbs().transpose());
  return static_cast<double>(A.cols() + 1) * std::numeric_limits<double>::epsilon() * (b.lpNorm<1>() + abs_ax);
}

/// b^T u accumulated in long double.
inline long double dotLong(const Eigen::VectorXd& b, const Eigen::VectorXd& u) {
  long double sum = 0.0L;
  for (Eigen::Index i = 0; i < b.size(); ++i) sum += static_cast<long double>(b[i]) * u[i];
  return sum;
}

/// (A^T u)_j accumulated in long double: the dual residual the bounds charge.
inline long double columnDotLong(const Eigen::MatrixXd& A, Eigen::Index j, const Eigen::VectorXd& u) {
  long double g = 0.0L;
  for (Eigen::Index i = 0; i < A.rows(); ++i) g += static_cast<long double>(A(i, j)) * u[i];
  return g;
}

/// 10 significant digits.
/// Throws std::invalid_argument("<who>: <what>").
[[noreturn]] inline void throwInput(const std::string& who, const std::string& what) {
  throw std::invalid_argument(who + ": " + what);
}

/// Every entry of v finite, else throws naming "<name>(i)" and the value.
inline void checkFinite(const std::string& who, const Eigen::VectorXd& v, const char* name) {
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i])) throwInput(who, std::string(name) + "(" + core::toText(i) + ") is not finite, got " + core::formatNumber(v[i], 10));
  }
}

/// A has at least one row and column, b has A's rows, both finite; else throws naming the entry.
inline void checkProblem(const std::string& who, const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  if (A.rows() == 0 || A.cols() == 0) {
    throwInput(who, "A must have at least one row and one column, got " + core::toText(A.rows()) + " x " +
                        core::toText(A.cols()));
  }
  if (b.size() != A.rows()) {
    throwInput(who, "expected b of size " + core::toText(A.rows()) + " (the rows of A), got " + core::toText(b.size()));
  }
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    for (Eigen::Index i = 0; i < A.rows(); ++i) {
      if (!std::isfinite(A(i, j))) {
        throwInput(who, "A(" + core::toText(i) + ", " + core::toText(j) + ") is not finite, got " + core::formatNumber(A(i, j), 10));
      }
    }
  }
  checkFinite(who, b, "b");
}

}  // namespace exoid::ident::lad_detail
