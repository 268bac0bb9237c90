#include "exoid/ident/model/base_parameters.hpp"

#include "exoid/core/format.hpp"
#include "exoid/core/random.hpp"
#include "exoid/ident/model/newton_euler.hpp"

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace exoid::ident {

void BaseParameterOptions::validate() const {
  if (samples < 1) throw std::invalid_argument("base parameters: 'samples' must be >= 1, got " + core::toText(samples));
  if (!(tolerance > 0.0 && tolerance < 1.0)) throw std::invalid_argument("base parameters: 'tolerance' must be in (0, 1), got " + core::toText(tolerance));
  if (!(coefficient_tolerance >= 0.0)) throw std::invalid_argument("base parameters: 'coefficient_tolerance' must be >= 0, got " + core::toText(coefficient_tolerance));
}

namespace {

Eigen::MatrixXd randomStateRegressor(const ChainModel& model, const BaseParameterOptions& o) {
  const int n = model.dof();
  Eigen::MatrixXd W(static_cast<Eigen::Index>(o.samples) * n, model.standardParameterCount());
  core::Rng rng(o.seed);
  ChainRegressorWorkspace work;
  Eigen::VectorXd q(n), qd(n), qdd(n);
  for (int s = 0; s < o.samples; ++s) {
    for (int i = 0; i < n; ++i) {
      q[i] = rng.uniform(-M_PI, M_PI);
      qd[i] = rng.uniform(-3.0, 3.0);
      qdd[i] = rng.uniform(-30.0, 30.0);
    }
    ChainBaseMotion base = ChainBaseMotion::still(model);
    if (o.planar_base_motion) {
      base.specific_force_mps2 = Eigen::Vector3d(rng.uniform(-20.0, 20.0), 0.0, rng.uniform(-20.0, 20.0));
      base.omega_radps = Eigen::Vector3d(0.0, rng.uniform(-3.0, 3.0), 0.0);
      base.alpha_radps2 = Eigen::Vector3d(0.0, rng.uniform(-30.0, 30.0), 0.0);
    }
    chainRegressorInto(model, q, qd, qdd, base, work, W.middleRows(static_cast<Eigen::Index>(s) * n, n));
  }
  return W;
}

std::string describe(const Eigen::RowVectorXd& row, int lead, const std::vector<std::string>& names) {
  std::ostringstream s;
  s << names[static_cast<std::size_t>(lead)];
  for (Eigen::Index k = 0; k < row.size(); ++k) {
    if (k == lead || row[k] == 0.0) continue;
    const double c = row[k];
    s << (c < 0.0 ? " - " : " + ");
    if (std::abs(std::abs(c) - 1.0) > 1e-12) s << core::formatNumber(std::abs(c), 6) << " ";
    s << names[static_cast<std::size_t>(k)];
  }
  return s.str();
}

}  // namespace

BaseParameters baseParameters(const ChainModel& model, const BaseParameterOptions& options) {
  model.validate();
  options.validate();
  const Eigen::MatrixXd W = randomStateRegressor(model, options);
  const Eigen::Index p = W.cols();
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(W);
  const Eigen::MatrixXd R = qr.matrixR().topRows(std::min(W.rows(), p)).triangularView<Eigen::Upper>();
  const double first = std::abs(R(0, 0));
  int r = 0;
  while (r < R.rows() && std::abs(R(r, r)) > options.tolerance * first) ++r;
  const Eigen::VectorXi perm = qr.colsPermutation().indices();

  BaseParameters out;
  out.rank = r;
  // K = R1^-1 R2: how each dependent column is made of the independent ones.
  Eigen::MatrixXd K = R.topLeftCorner(r, r).triangularView<Eigen::Upper>().solve(R.topRightCorner(r, p - r));
  K = K.unaryExpr([&](double v) { return std::abs(v) < options.coefficient_tolerance ? 0.0 : v; });
  out.combination = Eigen::MatrixXd::Zero(r, p);
  for (int i = 0; i < r; ++i) {
    out.independent.push_back(perm[i]);
    out.combination(i, perm[i]) = 1.0;
    for (Eigen::Index j = 0; j < p - r; ++j) out.combination(i, perm[r + j]) = K(i, j);
  }
  // In the standard parameters' order (base to tip), not the pivots': readable, and the same
  // order whatever the pivoting found first.
  std::vector<int> order(static_cast<std::size_t>(r));
  for (int i = 0; i < r; ++i) order[static_cast<std::size_t>(i)] = i;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return perm[a] < perm[b]; });
  const Eigen::MatrixXd pivot_rows = out.combination;
  const Eigen::MatrixXd K_pivot = K;
  for (int i = 0; i < r; ++i) {
    const int from = order[static_cast<std::size_t>(i)];
    out.combination.row(i) = pivot_rows.row(from);
    out.independent[static_cast<std::size_t>(i)] = perm[from];
    K.row(i) = K_pivot.row(from);
  }
  const std::vector<std::string> names = model.standardParameterNames();
  for (int i = 0; i < r; ++i) {
    const int lead = out.independent[static_cast<std::size_t>(i)];
    out.combinations.push_back(describe(out.combination.row(i), lead, names));
    const Eigen::Index others = (out.combination.row(i).array() != 0.0).count() - 1;
    out.names.push_back(names[static_cast<std::size_t>(lead)] +
                        (others > 0 ? " + " + core::toText(static_cast<long>(others)) + (others == 1 ? " term" : " terms") : std::string()));
  }
  const double column_scale = W.colwise().norm().maxCoeff();
  for (Eigen::Index j = 0; j < p - r; ++j) {
    const int k = perm[r + j];
    if (W.col(k).norm() <= options.tolerance * column_scale) {
      out.no_effect.push_back(k);
      continue;
    }
    std::vector<int> into;
    for (int i = 0; i < r; ++i) {
      if (K(i, j) != 0.0) into.push_back(i);
    }
    out.regrouped.emplace_back(k, into);
  }
  std::sort(out.no_effect.begin(), out.no_effect.end());
  std::sort(out.regrouped.begin(), out.regrouped.end());
  return out;
}

Eigen::MatrixXd BaseParameters::baseRegressor(const Eigen::MatrixXd& Y) const {
  Eigen::MatrixXd B(Y.rows(), rank);
  for (int i = 0; i < rank; ++i) B.col(i) = Y.col(independent[static_cast<std::size_t>(i)]);
  return B;
}

}  // namespace exoid::ident
