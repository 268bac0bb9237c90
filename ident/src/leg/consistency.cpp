#include "exoid/ident/leg/consistency.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/leg/params.hpp"

#include <Eigen/Cholesky>
#include <Eigen/QR>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace exoid::ident {

double ConsistencyCheck::t() const {
  if (std::isinf(standard_error)) return value < 0.0 ? -0.0 : 0.0;
  if (standard_error > 0.0) return value / standard_error;
  return value < 0.0 ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
}

bool ConsistencyCheck::significant(double sigmas) const { return violated() && t() < -sigmas; }

void ConsistencyOptions::validate() const {
  if (!(significance_sigmas > 0.0) || !std::isfinite(significance_sigmas)) {
    throw std::invalid_argument("'significance_sigmas' must be > 0, got " + core::toText(significance_sigmas));
  }
  if (!(gap_tolerance > 0.0 && gap_tolerance <= 1e-3)) {
    throw std::invalid_argument("'gap_tolerance' must be in (0, 1e-3], got " + core::toText(gap_tolerance));
  }
}

std::vector<std::string> ConsistentEstimate::significantViolations(double sigmas) const {
  std::vector<std::string> out;
  for (const ConsistencyCheck& c : checks) {
    if (!c.significant(sigmas)) continue;
    out.push_back(c.name + " violated by " + (std::isfinite(c.t()) ? core::formatNumber(-c.t(), 3) + " standard errors"
                                                                  : std::string("far more than its standard error (0)")) +
                  " (value " + core::formatNumber(c.value, 4) + ")");
  }
  return out;
}

namespace {
// Condition indices: the single-parameter ones first, then Jt - Js, then the cone.
constexpr int kSingle[] = {kFc1, kFv1, kFc2, kFv2, kJs};
constexpr int kNumSingle = 5;
}  // namespace

ConsistencyConditions::ConsistencyConditions(double lt, bool armature) : thigh_length_m(lt), knee_armature(armature) {
  if (!(lt > 0.0) || !std::isfinite(lt)) throw std::invalid_argument("consistency: thigh length must be > 0, got " + core::toText(lt));
}

int ConsistencyConditions::count() const { return kNumSingle + 2 + (knee_armature ? 1 : 0); }

std::string ConsistencyConditions::name(int i) const {
  if (i < kNumSingle) return std::string(paramName(kSingle[i])) + " >= 0";
  if (i == kNumSingle) return "Jt - Js >= 0";
  if (i == kNumSingle + 1) return "(Jt - Js) Js >= Lt^2 (Mxs^2 + Mys^2)";
  return "Ia2 >= 0";
}

double ConsistencyConditions::value(int i, const Eigen::VectorXd& x) const {
  if (i < kNumSingle) return x[kSingle[i]];
  if (i == kNumSingle) return x[kJt] - x[kJs];
  if (i == kNumSingle + 1) {
    const double l2 = thigh_length_m * thigh_length_m;
    return (x[kJt] - x[kJs]) * x[kJs] - l2 * (x[kMxs] * x[kMxs] + x[kMys] * x[kMys]);
  }
  return x[kKneeArmature];
}

Eigen::VectorXd ConsistencyConditions::gradient(int i, const Eigen::VectorXd& x) const {
  Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
  if (i < kNumSingle) {
    g[kSingle[i]] = 1.0;
  } else if (i == kNumSingle) {
    g[kJt] = 1.0;
    g[kJs] = -1.0;
  } else if (i == kNumSingle + 1) {
    const double l2 = thigh_length_m * thigh_length_m;
    g[kJt] = x[kJs];
    g[kJs] = x[kJt] - 2.0 * x[kJs];
    g[kMxs] = -2.0 * l2 * x[kMxs];
    g[kMys] = -2.0 * l2 * x[kMys];
  } else {
    g[kKneeArmature] = 1.0;
  }
  return g;
}

Eigen::MatrixXd ConsistencyConditions::hessian(int i, Eigen::Index n) const {
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n);
  if (i != kNumSingle + 1) return h;
  const double l2 = thigh_length_m * thigh_length_m;
  h(kJt, kJs) = h(kJs, kJt) = 1.0;
  h(kJs, kJs) = -2.0;
  h(kMxs, kMxs) = h(kMys, kMys) = -2.0 * l2;
  return h;
}

bool ConsistencyConditions::satisfied(const Eigen::VectorXd& x) const {
  for (int i = 0; i < count(); ++i) {
    if (!(value(i, x) >= 0.0)) return false;
  }
  return true;
}

namespace {

// A strictly feasible point near x: each violated condition pushed `margin` inside.
Eigen::VectorXd strictlyFeasible(const ConsistencyConditions& c, Eigen::VectorXd x, const Eigen::VectorXd& margin) {
  for (int k : kSingle) x[k] = std::max(x[k], margin[k]);
  if (c.knee_armature) x[kKneeArmature] = std::max(x[kKneeArmature], margin[kKneeArmature]);
  const double l2 = c.thigh_length_m * c.thigh_length_m;
  const double need = l2 * (x[kMxs] * x[kMxs] + x[kMys] * x[kMys]) / x[kJs];  // Jt - Js must exceed this
  x[kJt] = std::max(x[kJt], x[kJs] + 2.0 * need + margin[kJt]);
  return x;
}

// The barrier problem in scaled coordinates z (x = s .* z): t f(z) - sum log g_i.
struct Barrier {
  const ConsistencyConditions& cond;
  Eigen::MatrixXd G;  // S H^T H S / y^T y
  Eigen::VectorXd h;  // S H^T y / y^T y
  Eigen::VectorXd s;
  double cost(const Eigen::VectorXd& z) const { return 0.5 * z.dot(G * z) - h.dot(z); }
  // +inf outside the strictly feasible set.
  double value(const Eigen::VectorXd& z, double t) const {
    const Eigen::VectorXd x = s.cwiseProduct(z);
    double phi = t * cost(z);
    for (int i = 0; i < cond.count(); ++i) {
      const double g = cond.value(i, x);
      if (!(g > 0.0)) return std::numeric_limits<double>::infinity();
      phi -= std::log(g);
    }
    return phi;
  }
  void derivatives(const Eigen::VectorXd& z, double t, Eigen::VectorXd& grad, Eigen::MatrixXd& hess) const {
    const Eigen::VectorXd x = s.cwiseProduct(z);
    grad = t * (G * z - h);
    hess = t * G;
    for (int i = 0; i < cond.count(); ++i) {
      const double g = cond.value(i, x);
      const Eigen::VectorXd dg = s.cwiseProduct(cond.gradient(i, x));
      grad -= dg / g;
      hess += dg * dg.transpose() / (g * g) - s.asDiagonal() * cond.hessian(i, x.size()) * s.asDiagonal() / g;
    }
  }
};

}  // namespace

ConsistentEstimate solveConsistentLeastSquares(const Eigen::MatrixXd& H, const Eigen::VectorXd& y, double thigh_length_m,
                                               const Eigen::VectorXd& x_ls, const Eigen::MatrixXd& covariance,
                                               const ConsistencyOptions& options) {
  options.validate();
  const Eigen::Index n = H.cols();
  if (n != kNumParams && n != kNumParams + 1) {
    throw std::invalid_argument("consistent least squares: expected 10 or 11 columns (X, Ia2), got " + core::toText(n));
  }
  if (H.rows() != y.size() || x_ls.size() != n || covariance.rows() != n || covariance.cols() != n) {
    throw std::invalid_argument("consistent least squares: sizes of H, y, the estimate and its covariance disagree");
  }
  if (!H.allFinite() || !y.allFinite() || !x_ls.allFinite()) {
    throw std::invalid_argument("consistent least squares: regressor, torque or estimate contains NaN or Inf");
  }
  const ConsistencyConditions cond(thigh_length_m, n == kNumParams + 1);
  ConsistentEstimate out;
  out.x = x_ls;
  for (int i = 0; i < cond.count(); ++i) {
    ConsistencyCheck c;
    c.name = cond.name(i);
    c.value = cond.value(i, x_ls);
    const Eigen::VectorXd dg = cond.gradient(i, x_ls);
    const double var = dg.dot(covariance * dg);
    c.standard_error = covariance.allFinite() ? std::sqrt(std::max(var, 0.0)) : std::numeric_limits<double>::infinity();
    out.checks.push_back(c);
  }
  if (cond.satisfied(x_ls)) return out;

  const Eigen::VectorXd s = columnScales(H);
  const double yy = y.squaredNorm();
  if (!(yy > 0.0)) throw std::invalid_argument("consistent least squares: the torque is zero");
  Barrier b{cond, s.asDiagonal() * (H.transpose() * H) * s.asDiagonal() / yy, s.asDiagonal() * (H.transpose() * y) / yy, s};
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> rank_qr(H * s.asDiagonal());
  rank_qr.setThreshold(LsOptions{}.rank_tolerance);  // least squares' own rank rule
  if (rank_qr.rank() < n) throw std::invalid_argument("consistent least squares: the regressor is rank deficient");
  // Margins: a 0.1 % share of the torque's norm in each column's units.
  const Eigen::VectorXd margin = 1e-3 * std::sqrt(yy) * s;
  Eigen::VectorXd z = strictlyFeasible(cond, x_ls, margin).cwiseQuotient(s);
  const double m = cond.count();
  Eigen::VectorXd grad;
  Eigen::MatrixXd hess;
  for (double t = 1.0;; t *= 10.0) {
    for (int step = 0; step < 200; ++step) {  // centring by damped Newton
      b.derivatives(z, t, grad, hess);
      const Eigen::VectorXd dz = -hess.ldlt().solve(grad);
      const double decrement2 = -grad.dot(dz);
      if (!(decrement2 > 1e-20)) break;
      const double phi = b.value(z, t);
      double alpha = 1.0;
      while (alpha > 1e-16 && !(b.value(z + alpha * dz, t) <= phi - 0.25 * alpha * decrement2)) alpha *= 0.5;
      if (alpha <= 1e-16) break;  // rounding floor of phi: centred as well as double allows
      z += alpha * dz;
    }
    if (m / t < options.gap_tolerance) break;
  }
  out.x = s.cwiseProduct(z);
  out.constrained = true;
  for (int i = 0; i < cond.count(); ++i) {
    // On the boundary: the barrier keeps g ~ m / t there, far below any interior value.
    const double scale = std::abs(out.checks[static_cast<std::size_t>(i)].value) + cond.gradient(i, out.x).cwiseAbs().dot(out.x.cwiseAbs());
    out.checks[static_cast<std::size_t>(i)].active = cond.value(i, out.x) <= 1e-6 * scale;
  }
  return out;
}

}  // namespace exoid::ident
