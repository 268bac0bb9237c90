#include "exoid/ident/estimators/lad.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/estimators/least_squares.hpp"
#include "lad_common.hpp"
#include "exoid/ident/estimators/stopwatch.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

// The linear program and its dual (u = a - s, a + s = 1, a, s >= 0):
//   primal  min_{x,w,z} 1^T w + 1^T z  s.t.  A x + w - z = b,   w, z >= 0
//   dual    max_u       b^T u          s.t.  A^T u = 0,  -1 <= u <= 1
// Complementarity pairs: a_i z_i = 0 and s_i w_i = 0, so u_i = sign(b_i - a_i^T x) away from zero
// residuals. Any dual-feasible u bounds the optimum from below: for every x,
//   ||b - A x||_1 >= u^T (b - A x) = b^T u - x^T A^T u = b^T u.
// The interior point (Mehrotra predictor-corrector) keeps a, s, w, z > 0 and eliminates every
// N-vector of its Newton system, leaving the p x p system (A^T Q A) dy = rhs, Q = diag(q),
// q_i = 1 / (w_i / s_i + z_i / a_i).
namespace exoid::ident {
namespace {

using lad_detail::l1Cost;
using lad_detail::roundingLevel;

/// Pivots |R_kk| < kRankTolerance * |R_00| of the column-scaled A are treated as zero; the same
/// default as least squares (LsOptions::rank_tolerance): a scaled condition number above 1e8
/// would also square to ~1e16 in the interior point's normal equations.
constexpr double kRankTolerance = 1e-8;
/// Fraction of the distance to the boundary taken by a step (Portnoy & Koenker use 0.99995).
constexpr double kStepFraction = 0.99995;
constexpr double kEps = std::numeric_limits<double>::epsilon();


/// "rank r < p: column k is a linear combination of columns {i, j}" for each column beyond the
/// numerical rank of the pivoted QR (coefficients from R11^{-1} R12 in the scaled columns, where
/// a coefficient above 1e-8 is a real participant; a zero column has none).
std::string rankDeficiencyMessage(const Eigen::ColPivHouseholderQR<Eigen::MatrixXd>& qr,
                                  Eigen::Index p) {
  const Eigen::Index rank = qr.rank();
  const auto& perm = qr.colsPermutation().indices();
  const Eigen::MatrixXd R = qr.matrixR().topRows(rank);
  std::string msg = "rank " + core::toText(rank) + " < " + core::toText(p) + ":";
  for (Eigen::Index k = rank; k < p; ++k) {
    Eigen::VectorXd c = Eigen::VectorXd::Zero(rank);
    if (rank > 0) {
      c = R.leftCols(rank).triangularView<Eigen::Upper>().solve(R.col(k));
    }
    std::vector<Eigen::Index> with;
    for (Eigen::Index i = 0; i < rank; ++i) {
      if (std::abs(c[i]) > 1e-8) with.push_back(perm[i]);
    }
    std::sort(with.begin(), with.end());
    msg += (k == rank ? " column " : "; column ") + core::toText(perm[k]);
    if (with.empty()) {
      msg += " is (numerically) zero";
    } else {
      msg += " is a linear combination of column" + std::string(with.size() > 1 ? "s" : "") + " {";
      for (std::size_t i = 0; i < with.size(); ++i) {
        msg += (i ? ", " : "") + core::toText(with[i]);
      }
      msg += "}";
    }
  }
  return msg;
}



/// Makes u dual feasible and returns its lower bound on the optimum. u is projected onto the null
/// space of A^T (least squares on the QR of the scaled A, whose null space is the same) and then
/// divided by max(1, max|u_i|), so |u_i| <= 1 holds exactly and A^T u = 0 up to roundoff. The bound
/// is b^T u - |x|^T |A^T u|: weak duality b^T u - x^T A^T u with the leftover dual residual charged
/// at its worst sign, evaluated at the returned x (the optimum's neighbour); sums in long double.
double dualBound(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::MatrixXd& As,
                 const Eigen::ColPivHouseholderQR<Eigen::MatrixXd>& qr, const Eigen::VectorXd& x,
                 Eigen::VectorXd& u) {
  const Eigen::VectorXd t = qr.solve(u);
  u.noalias() -= As * t;
  const double m = u.cwiseAbs().maxCoeff();
  if (m > 1.0) u /= m;
  const long double bu = lad_detail::dotLong(b, u);
  long double charge = 0.0L;
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    charge += std::abs(lad_detail::columnDotLong(A, j, u)) * std::abs(static_cast<long double>(x[j]));
  }
  return static_cast<double>(bu - charge);
}

/// A vertex next to the interior-point solution and its basic dual.
struct Vertex {
  bool found = false;
  Eigen::VectorXd x;  ///< A_B x = b_B, original units
  Eigen::VectorXd u;  ///< dual: sign of the nonbasic residuals, basic part from A^T u = 0
  double max_basic_u = 0.0;  ///< <= 1 certifies the vertex optimal
};

/// Purification: the p rows with the smallest |residual| that are linearly independent (greedy,
/// Gram-Schmidt on the rows of the column-scaled As) form a basis B and x solves A_B x = b_B
/// (LU with partial pivoting, which column scaling does not change, in original units so that
/// e.g. a median comes out as the data value itself). The dual takes u_i = sign(r_i) off the
/// basis, except where r_i is at its roundoff level (a degenerate vertex) where the interior
/// point's u_i is kept, and solves As_B^T u_B = -As_N^T u_N.
Vertex purify(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::MatrixXd& As,
              const Eigen::VectorXd& r, const Eigen::VectorXd& u_ip) {
  const Eigen::Index n = As.rows();
  const Eigen::Index p = As.cols();
  Vertex v;
  std::vector<Eigen::Index> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  const auto by_abs = [&r](Eigen::Index i, Eigen::Index j) { return std::abs(r[i]) < std::abs(r[j]); };
  // Sort a short head first; the whole order is only needed when the head holds no basis.
  std::size_t sorted = std::min(order.size(), static_cast<std::size_t>(4 * p + 8));
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(sorted), order.end(),
                    by_abs);
  Eigen::MatrixXd Q(p, p);  // orthonormal rows spanning the chosen rows
  std::vector<Eigen::Index> basis;
  for (std::size_t k = 0; k < order.size() && static_cast<Eigen::Index>(basis.size()) < p; ++k) {
    if (k == sorted) {
      std::sort(order.begin() + static_cast<std::ptrdiff_t>(sorted), order.end(), by_abs);
      sorted = order.size();
    }
    const Eigen::Index i = order[k];
    Eigen::VectorXd row = As.row(i).transpose();
    const double norm0 = row.norm();
    if (norm0 == 0.0) continue;
    const auto m = static_cast<Eigen::Index>(basis.size());
    for (int pass = 0; pass < 2; ++pass) {
      for (Eigen::Index k2 = 0; k2 < m; ++k2) row -= Q.row(k2).dot(row) * Q.row(k2).transpose();
    }
    const double norm = row.norm();
    if (norm <= 1e-8 * norm0) continue;
    Q.row(m) = row.transpose() / norm;
    basis.push_back(i);
  }
  if (static_cast<Eigen::Index>(basis.size()) < p) return v;

  Eigen::MatrixXd AB(p, p), AsB(p, p);
  Eigen::VectorXd bB(p);
  for (Eigen::Index k = 0; k < p; ++k) {
    const Eigen::Index i = basis[static_cast<std::size_t>(k)];
    AB.row(k) = A.row(i);
    AsB.row(k) = As.row(i);
    bB[k] = b[i];
  }
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(AB);
  v.x = lu.solve(bB);
  v.x += lu.solve(bB - AB * v.x);  // one step of iterative refinement

  const Eigen::VectorXd rv = b - A * v.x;
  const Eigen::RowVectorXd abs_x = v.x.cwiseAbs().transpose();
  v.u.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double roundoff = 8.0 * static_cast<double>(p + 1) * kEps *
                            (std::abs(b[i]) + A.row(i).cwiseAbs().dot(abs_x));
    if (std::abs(rv[i]) > roundoff) {
      v.u[i] = rv[i] > 0.0 ? 1.0 : -1.0;
    } else {
      v.u[i] = std::clamp(u_ip[i], -1.0, 1.0);
    }
  }
  for (const Eigen::Index i : basis) v.u[i] = 0.0;
  const Eigen::VectorXd rhs = -(As.transpose() * v.u);
  const Eigen::VectorXd uB = Eigen::PartialPivLU<Eigen::MatrixXd>(AsB).transpose().solve(rhs);
  for (Eigen::Index k = 0; k < p; ++k) v.u[basis[static_cast<std::size_t>(k)]] = uB[k];
  v.max_basic_u = uB.cwiseAbs().maxCoeff();
  v.found = v.x.allFinite() && v.u.allFinite();
  return v;
}

/// Largest step in (0, 1] (times kStepFraction) keeping x1 + alpha dx1 > 0 and
/// x2 + alpha sign2 dx2 > 0, from the largest rate -dx / x (branch free, so it vectorises).
double stepLength(const Eigen::VectorXd& x1, const Eigen::VectorXd& dx1, const Eigen::VectorXd& x2,
                  const Eigen::VectorXd& dx2, double sign2) {
  const double rate = std::max({0.0, (-dx1.array() / x1.array()).maxCoeff(),
                                ((-sign2) * dx2.array() / x2.array()).maxCoeff()});
  return rate > kStepFraction ? kStepFraction / rate : 1.0;
}

// The scaled problem: columns to unit norm, b to unit mean |b|; x = b_scale * D y.
struct ScaledProblem {
  ScaledProblem(const Eigen::MatrixXd& A, const Eigen::VectorXd& b)
      : D(columnScales(A)), As(A * D.asDiagonal()), b_scale(b.cwiseAbs().mean() > 0.0 ? b.cwiseAbs().mean() : 1.0), bs(b / b_scale) {}
  Eigen::VectorXd unscale(const Eigen::VectorXd& y) const { return b_scale * D.cwiseProduct(y); }
  Eigen::VectorXd D;
  Eigen::MatrixXd As;
  double b_scale;
  Eigen::VectorXd bs;
};

// u = 0 is dual feasible (bound 0) and x = 0 costs ||b||_1: an honest, unusable pair.
LadResult rankDeficientResult(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                              const Eigen::ColPivHouseholderQR<Eigen::MatrixXd>& qr, const Stopwatch& clock) {
  LadResult result;
  const Eigen::Index p = A.cols();
  result.x = Eigen::VectorXd::Zero(p);
  result.cost = l1Cost(A, b, result.x);
  result.dual_bound = 0.0;
  result.dual = Eigen::VectorXd::Zero(A.rows());
  result.gap = result.cost;
  result.summary.status = Status::kRankDeficient;
  result.summary.message = rankDeficiencyMessage(qr, p);
  result.summary.initial_cost = result.cost;
  result.summary.final_cost = result.cost;
  result.summary.wall_time_s = clock.seconds();
  return result;
}

// Frisch-Newton interior point with Mehrotra's predictor-corrector on the scaled problem. The
// iterate: y (primal), a and s (u = a - s, the dual), w and z (the residual's positive and
// negative parts). Every vector is allocated once: nothing in iterate() allocates.
class InteriorPoint {
 public:
  InteriorPoint(const ScaledProblem& sp, const Eigen::VectorXd& y_ls, double tol, int max_iterations)
      : y(y_ls), sp_(sp), n_(sp.As.rows()), p_(sp.As.cols()), tol_(tol), max_iterations_(max_iterations) {
    // Start: y at least squares, a = s = 1/2 (u = 0), w - z = r with both >= delta > 0 (a tenth
    // of the mean |residual|: fewer iterations than 0.01 or 1 over a sweep of problems). Both
    // equality constraints hold exactly, so the iteration only has to drive complementarity down.
    r = sp.bs - sp.As * y;
    const double delta = std::max(0.1 * r.cwiseAbs().mean(), 1e-3);
    a = Eigen::VectorXd::Constant(n_, 0.5);
    s = Eigen::VectorXd::Constant(n_, 0.5);
    w = r.cwiseMax(0.0).array() + delta;
    z = (-r).cwiseMax(0.0).array() + delta;
    for (Eigen::VectorXd* v : {&q, &rd, &rhat, &ra, &rs, &tmp, &da, &dz, &dw}) v->resize(n_);
    QA.resize(n_, p_);
    M.resize(p_, p_);
    for (Eigen::VectorXd* v : {&rp, &rhs, &dy}) v->resize(p_);
    best_y = y;
    // What double precision can resolve in the scaled cost at y (see roundingLevel).
    As_col_l1 = sp.As.cwiseAbs().colwise().sum();
    bs_l1 = sp.bs.lpNorm<1>();
  }

  /// Iterates until the gap test, the limit or a breakdown; returns why it stopped.
  std::string run() {
    for (;;) {
      if (const std::string why = stopTest(); !why.empty()) return why;
      ++iterations;
      if (!normalEquations()) return "singular normal equations at iteration " + core::toText(iterations);
      predictorCorrector();
    }
  }

  long iterations = 0;
  Eigen::VectorXd y, best_y, r, a, s, w, z;

 private:
  // Residuals and the stopping test on the current iterate ("" = go on); tracks the best y.
  std::string stopTest() {
    const Eigen::MatrixXd& As = sp_.As;
    r = sp_.bs;
    r.noalias() -= As * y;
    rd = r - w + z;
    tmp = a - s;
    rp.noalias() = As.transpose() * tmp;
    rp *= -0.5;
    const double cost = r.cwiseAbs().sum();
    const double gap = cost - sp_.bs.dot(tmp);
    mu_ = (a.dot(z) + s.dot(w)) / (2.0 * static_cast<double>(n_));
    if (!std::isfinite(gap) || !std::isfinite(mu_)) return "non-finite iterate at iteration " + core::toText(iterations);
    if (cost < best_cost_) {
      best_cost_ = cost;
      best_y = y;
    }
    const double rounding = static_cast<double>(p_ + 1) * kEps * (bs_l1 + As_col_l1.dot(y.cwiseAbs()));
    if (gap <= std::max(0.5 * tol_ * std::max(1.0 / sp_.b_scale, cost), rounding)) return "gap below tolerance";
    if (iterations >= max_iterations_) return "iteration limit";
    return {};
  }

  // Normal equations M = As^T Q As; LLT, else LDLT, else LLT with a tiny ridge. False if singular.
  bool normalEquations() {
    const Eigen::MatrixXd& As = sp_.As;
    q = (w.cwiseQuotient(s) + z.cwiseQuotient(a)).cwiseInverse();
    QA = q.asDiagonal() * As;
    for (Eigen::Index j = 0; j < p_; ++j) {
      for (Eigen::Index k = j; k < p_; ++k) M(k, j) = M(j, k) = QA.col(j).dot(As.col(k));
    }
    llt_.compute(M);
    use_ldlt_ = llt_.info() != Eigen::Success;
    if (!use_ldlt_) return true;
    ldlt_.compute(M);
    if (ldlt_.info() == Eigen::Success && (ldlt_.vectorD().array() > 0.0).all()) return true;
    M.diagonal().array() += 1e3 * kEps * M.diagonal().maxCoeff();
    llt_.compute(M);
    use_ldlt_ = false;
    return llt_.info() == Eigen::Success;
  }

  // The Newton direction (da, dy, dz, dw; ds = -da) for the feasibility residuals rp, rd and the
  // complementarity right-hand sides ra (pairs a z) and rs (pairs s w), by eliminating dz, dw:
  //   dz = (ra - z da) / a,  dw = (rs + w da) / s,  da = q (rhat - As dy),
  //   rhat = rd + ra / a - rs / s,  (As^T Q As) dy = As^T Q rhat - rp.
  void direction() {
    rhat = rd + ra.cwiseQuotient(a) - rs.cwiseQuotient(s);
    rhs.noalias() = QA.transpose() * rhat;
    rhs -= rp;
    if (use_ldlt_) {
      dy = ldlt_.solve(rhs);
    } else {
      dy = llt_.solve(rhs);
    }
    tmp.noalias() = sp_.As * dy;
    da = q.cwiseProduct(rhat - tmp);
    dz = (ra - z.cwiseProduct(da)).cwiseQuotient(a);
    dw = (rs + w.cwiseProduct(da)).cwiseQuotient(s);
  }

  void predictorCorrector() {
    const double nd = static_cast<double>(n_);
    // Predictor (affine scaling): drive every product to zero.
    ra = -a.cwiseProduct(z);
    rs = -s.cwiseProduct(w);
    direction();
    double alpha_p = stepLength(a, da, s, da, -1.0);
    double alpha_d = stepLength(z, dz, w, dw, 1.0);
    const double mu_aff = ((a + alpha_p * da).dot(z + alpha_d * dz) + (s - alpha_p * da).dot(w + alpha_d * dw)) / (2.0 * nd);
    const double sigma_mu = std::pow(mu_aff / mu_, 3) * mu_;
    // Mehrotra corrector: target sigma mu, with the predictor's second-order term.
    ra = (sigma_mu - a.cwiseProduct(z).array()).matrix() - da.cwiseProduct(dz);
    rs = (sigma_mu - s.cwiseProduct(w).array()).matrix() + da.cwiseProduct(dw);
    direction();
    alpha_p = stepLength(a, da, s, da, -1.0);
    alpha_d = stepLength(z, dz, w, dw, 1.0);
    a += alpha_p * da;
    s -= alpha_p * da;
    y += alpha_d * dy;
    z += alpha_d * dz;
    w += alpha_d * dw;
  }

  const ScaledProblem& sp_;
  const Eigen::Index n_, p_;
  const double tol_;
  const int max_iterations_;
  double mu_ = 0.0, best_cost_ = std::numeric_limits<double>::infinity();
  Eigen::VectorXd q, rd, rhat, ra, rs, tmp, da, dz, dw, rp, rhs, dy;
  Eigen::MatrixXd QA, M;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::LDLT<Eigen::MatrixXd> ldlt_;
  bool use_ldlt_ = false;
  Eigen::RowVectorXd As_col_l1;
  double bs_l1 = 0.0;
};

// Certificate: the interior point's own (x, u), then its purified vertex; keep the lower cost
// and the higher bound (each bound is valid on its own). Returns whether x is the vertex.
bool certify(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const ScaledProblem& sp,
             const Eigen::ColPivHouseholderQR<Eigen::MatrixXd>& qr, InteriorPoint& ip, LadResult& result, bool& exact_dual) {
  Eigen::VectorXd u_ip = ip.a - ip.s;
  if (!u_ip.allFinite()) u_ip.setZero();  // after a numerical breakdown: u = 0 is feasible
  ip.r = sp.bs - sp.As * ip.best_y;
  result.x = sp.unscale(ip.best_y);
  result.cost = l1Cost(A, b, result.x);
  const Vertex vertex = purify(A, b, sp.As, ip.r, u_ip);
  bool at_vertex = false;
  if (vertex.found) {
    const double cost_v = l1Cost(A, b, vertex.x);
    if (cost_v <= result.cost) {
      result.x = vertex.x;
      result.cost = cost_v;
      at_vertex = true;
    }
  }
  double bound = dualBound(A, b, sp.As, qr, result.x, u_ip);
  result.dual = u_ip;
  if (vertex.found) {
    Eigen::VectorXd uv = vertex.u;
    const double bound_v = dualBound(A, b, sp.As, qr, result.x, uv);
    if (bound_v > bound) {
      bound = bound_v;
      result.dual = std::move(uv);
    }
  }
  // Weak duality makes cost >= bound; a difference below zero is rounding and is reported as 0.
  result.dual_bound = std::min(bound, result.cost);
  result.gap = result.cost - result.dual_bound;
  exact_dual = vertex.found && at_vertex && vertex.max_basic_u <= 1.0;
  return at_vertex;
}

}  // namespace

void LadOptions::validate() const {
  if (!(gap_tolerance > 0.0 && gap_tolerance < 1.0)) {
    throw std::invalid_argument("'gap_tolerance' must be in (0, 1), got " + core::formatNumber(gap_tolerance, 10));
  }
  if (max_iterations < 1) {
    throw std::invalid_argument("'max_iterations' must be >= 1, got " +
                                core::toText(max_iterations));
  }
}

LadResult solveLeastAbsoluteDeviations(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                                       const LadOptions& options) {
  options.validate();
  lad_detail::checkProblem("least absolute deviations", A, b);
  const Stopwatch clock;
  const ScaledProblem sp(A, b);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(sp.As);
  qr.setThreshold(kRankTolerance);
  if (qr.rank() < A.cols()) return rankDeficientResult(A, b, qr, clock);

  LadResult result;
  InteriorPoint ip(sp, qr.solve(sp.bs), options.gap_tolerance, options.max_iterations);
  result.summary.initial_cost = l1Cost(A, b, sp.unscale(ip.y));
  const std::string stop_reason = ip.run();
  bool exact_dual = false;
  const bool at_vertex = certify(A, b, sp, qr, ip, result, exact_dual);

  const double allowed = std::max(options.gap_tolerance * std::max(1.0, std::abs(result.cost)), roundingLevel(A, b, result.x));
  result.summary.iterations = ip.iterations;
  result.summary.final_cost = result.cost;
  result.summary.status = result.gap <= allowed ? Status::kConverged : Status::kMaxIterations;
  result.summary.message = (result.summary.status == Status::kConverged ? "converged" : "stopped") +
                           std::string(" after ") + core::toText(ip.iterations) +
                           " interior-point iterations (" + stop_reason + "); gap " +
                           core::formatNumber(result.gap, 10) + (result.gap <= allowed ? " <= " : " > ") +
                           core::formatNumber(allowed, 10) + (at_vertex ? "; purified to a vertex" : "");
  if (exact_dual) result.summary.message += " with an exact basic dual";
  result.summary.wall_time_s = clock.seconds();
  return result;
}

}  // namespace exoid::ident
