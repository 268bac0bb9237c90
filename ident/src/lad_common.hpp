#pragma once
// Pieces both LAD solvers (lad.cpp, lad_box.cpp) use: the L1 cost in long double, the rounding
// level below which no two costs can be told apart, and the number format of their messages.
#include <Eigen/Core>

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
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

/// 10 significant digits.
inline std::string str(double v) {
  std::ostringstream os;
  os << std::setprecision(10) << v;
  return os.str();
}

}  // namespace exoid::ident::lad_detail
