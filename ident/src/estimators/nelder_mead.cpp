#include "exoid/ident/estimators/nelder_mead.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

namespace exoid::ident {

void NelderMeadOptions::validate() const {
  if (!(initial_step > 0 && std::isfinite(initial_step))) throw std::invalid_argument("'initial_step' must be > 0");
  if (max_evaluations < 1) throw std::invalid_argument("'max_evaluations' must be >= 1");
  if (!(f_tolerance >= 0)) throw std::invalid_argument("'f_tolerance' must be >= 0");
  if (!(x_tolerance >= 0)) throw std::invalid_argument("'x_tolerance' must be >= 0");
}

NelderMeadResult minimizeNelderMead(const std::function<double(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x0,
                                    const NelderMeadOptions& o) {
  o.validate();
  const Eigen::Index n = x0.size();
  if (n < 1) throw std::invalid_argument("Nelder-Mead: empty starting point");
  if (!x0.allFinite()) throw std::invalid_argument("Nelder-Mead: non-finite starting point");
  const double dn = static_cast<double>(n);
  // Gao-Han adaptive coefficients (the classic 1, 2, 0.5, 0.5 for n = 2).
  const double alpha = 1.0, beta = 1.0 + 2.0 / dn, gamma = 0.75 - 0.5 / dn, delta = 1.0 - 1.0 / dn;
  NelderMeadResult r;
  const auto eval = [&](const Eigen::VectorXd& x) {
    ++r.evaluations;
    const double v = f(x);
    return std::isfinite(v) ? v : std::numeric_limits<double>::infinity();
  };
  std::vector<Eigen::VectorXd> xs(static_cast<std::size_t>(n + 1), x0);
  std::vector<double> fs(static_cast<std::size_t>(n + 1));
  for (Eigen::Index i = 0; i < n; ++i) xs[static_cast<std::size_t>(i + 1)][i] += o.initial_step;
  for (std::size_t i = 0; i < xs.size(); ++i) fs[i] = eval(xs[i]);
  std::vector<std::size_t> order(xs.size());
  while (true) {
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return fs[a] < fs[b]; });
    const std::size_t best = order.front(), worst = order.back(), second = order[order.size() - 2];
    double spread_x = 0.0;
    for (std::size_t i : order) spread_x = std::max(spread_x, (xs[i] - xs[best]).cwiseAbs().maxCoeff());
    if (std::isfinite(fs[worst]) && fs[worst] - fs[best] <= o.f_tolerance && spread_x <= o.x_tolerance) {
      r.converged = true;
      break;
    }
    if (r.evaluations >= o.max_evaluations) break;
    Eigen::VectorXd centroid = Eigen::VectorXd::Zero(n);
    for (std::size_t i : order) {
      if (i != worst) centroid += xs[i];
    }
    centroid /= dn;
    const Eigen::VectorXd xr = centroid + alpha * (centroid - xs[worst]);
    const double fr = eval(xr);
    if (fr < fs[best]) {
      const Eigen::VectorXd xe = centroid + beta * (xr - centroid);
      const double fe = eval(xe);
      if (fe < fr) {
        xs[worst] = xe;
        fs[worst] = fe;
      } else {
        xs[worst] = xr;
        fs[worst] = fr;
      }
      continue;
    }
    if (fr < fs[second]) {
      xs[worst] = xr;
      fs[worst] = fr;
      continue;
    }
    // Contraction: outside if the reflection improved on the worst, inside otherwise.
    const bool outside = fr < fs[worst];
    const Eigen::VectorXd xc = outside ? Eigen::VectorXd(centroid + gamma * (xr - centroid))
                                       : Eigen::VectorXd(centroid - gamma * (centroid - xs[worst]));
    const double fc = eval(xc);
    if (fc < (outside ? fr : fs[worst])) {
      xs[worst] = xc;
      fs[worst] = fc;
      continue;
    }
    // Shrink towards the best vertex.
    for (std::size_t i : order) {
      if (i == best) continue;
      xs[i] = xs[best] + delta * (xs[i] - xs[best]);
      fs[i] = eval(xs[i]);
    }
  }
  const auto it = std::min_element(fs.begin(), fs.end());
  r.x = xs[static_cast<std::size_t>(it - fs.begin())];
  r.f = *it;
  return r;
}

}  // namespace exoid::ident
