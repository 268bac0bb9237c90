#include "exoid/ident/estimators/lad_box.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/estimators/stopwatch.hpp"
#include "lad_common.hpp"

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

// Exact penalty. With c_j = ||A_j||_1 and the augmented cost
//   F(x) = ||b - A x||_1 + sum_j c_j (|upper_j - x_j| + |x_j - lower_j|),
// F = cost + K inside the box, K = sum_j c_j (upper_j - lower_j). For x outside, its clamp x'
// satisfies cost(x') <= cost(x) + sum_j ||A_j||_1 |x_j - x'_j| (each row moves by at most
// sum_j |A_ij| |x_j - x'_j|) while the penalty falls by 2 sum_j c_j |x_j - x'_j|, so
// F(x') <= F(x) - sum_j c_j |x_j - x'_j| < F(x): every minimiser of F is in the box, where F is
// the cost plus a constant. Any c_j > ||A_j||_1 / 2 would do; c_j = ||A_j||_1 leaves a margin.
//
// Certificate (weak duality for the box): for every x in the box and every |u_i| <= 1,
//   ||b - A x||_1 >= u^T (b - A x) = b^T u - g^T x >= b^T u - sum_j max(lower_j g_j, upper_j g_j),
// g = A^T u. If (u, v+, v-) is dual feasible for the penalised problem, its data part u gives a
// box bound no lower than the penalised bound minus K (check the two signs of the max), so the
// box gap is at most the penalised one. At a box optimum the bound is tight for the u with
// g_j = 0 on free coordinates, g_j >= 0 on those at upper_j and g_j <= 0 on those at lower_j.
//
// The penalty rows limit what pass 1 can resolve to rounding of the size eps c_j |bounds|; when
// that is not enough (boxes far wider than |x|), pass 2 holds the active bounds and solves for the
// rest without penalty rows (activeSetPass), and refineDual removes the roundoff of g that the
// bound charges at the far edges of such a box.
namespace exoid::ident {
namespace {

using lad_detail::l1Cost;
using lad_detail::roundingLevel;

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
/// A coordinate this close to a bound, relative to the box width, is tried on it (see intoBox):
/// far above the rounding of a vertex solve, far below any distance PSO resolves.
constexpr double kSnapTolerance = 1e-9;
/// refineDual moves only entries with |u_i| below this: corrections are ~1e-12 and must not be
/// clipped at +-1, which would leave part of the roundoff in place.
constexpr double kRoom = 1.0 - 1e-9;
/// Floor of the penalised tolerance (LadOptions needs > 0); below it only rounding stops.
constexpr double kTiny = std::numeric_limits<double>::min();


constexpr const char kWho[] = "boxed least absolute deviations";

[[noreturn]] void throwInput(const std::string& what) { lad_detail::throwInput(kWho, what); }

void checkInputs(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Box& box) {
  lad_detail::checkProblem(kWho, A, b);
  if (box.lower.size() != A.cols() || box.upper.size() != A.cols()) {
    throwInput("expected a box of dimension " + core::toText(A.cols()) +
               " (the columns of A), got lower of size " + core::toText(box.lower.size()) +
               " and upper of size " + core::toText(box.upper.size()));
  }
  lad_detail::checkFinite(kWho, box.lower, "box.lower");
  lad_detail::checkFinite(kWho, box.upper, "box.upper");
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    if (!(box.lower[j] < box.upper[j])) {
      throwInput("box.lower(" + core::toText(j) + ") = " + core::formatNumber(box.lower[j], 10) +
                 " must be < box.upper(" + core::toText(j) + ") = " + core::formatNumber(box.upper[j], 10));
    }
  }
}



/// The penalised problem [A; diag(c); diag(c)] x ~ [b; c .* upper; c .* lower] and its in-box
/// constant K = sum_j c_j (upper_j - lower_j).
struct Penalised {
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
  double constant = 0.0;
};

/// c_j = ||A_j||_1 (see the top of the file). A (numerically) zero column leaves x_j free in the
/// data, so any c_j > 0 is exact; the floor 1e-8 max_k c_k (or 1 when A = 0) keeps the column
/// from vanishing next to the others in the solver's column scaling.
Penalised penalise(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Box& box) {
  const Eigen::Index n = A.rows();
  const Eigen::Index p = A.cols();
  Eigen::VectorXd c = A.cwiseAbs().colwise().sum().transpose();
  const double largest = c.maxCoeff();
  c = c.cwiseMax(largest > 0.0 ? 1e-8 * largest : 1.0);
  Penalised pen;
  pen.A = Eigen::MatrixXd::Zero(n + 2 * p, p);
  pen.A.topRows(n) = A;
  pen.A.middleRows(n, p).diagonal() = c;
  pen.A.bottomRows(p).diagonal() = c;
  pen.b.resize(n + 2 * p);
  pen.b << b, c.cwiseProduct(box.upper), c.cwiseProduct(box.lower);
  pen.constant = c.dot(box.upper - box.lower);
  return pen;
}

/// Clamps x into the box, then puts each coordinate within kSnapTolerance of the width from a
/// bound exactly on it, one at a time, keeping each move that leaves the cost within the rounding
/// level of the clamped point's: a parameter the data holds just inside a bound stays there.
Eigen::VectorXd intoBox(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Box& box,
                        const Eigen::VectorXd& x) {
  Eigen::VectorXd y = x.cwiseMax(box.lower).cwiseMin(box.upper);
  const double limit = l1Cost(A, b, y) + roundingLevel(A, b, y);
  for (Eigen::Index j = 0; j < y.size(); ++j) {
    const double near = kSnapTolerance * (box.upper[j] - box.lower[j]);
    const double keep = y[j];
    if (keep == box.lower[j] || keep == box.upper[j]) continue;
    if (keep - box.lower[j] <= near) {
      y[j] = box.lower[j];
    } else if (box.upper[j] - keep <= near) {
      y[j] = box.upper[j];
    } else {
      continue;
    }
    if (l1Cost(A, b, y) > limit) y[j] = keep;
  }
  return y;
}

std::vector<int> activeBounds(const Eigen::VectorXd& x, const Box& box) {
  std::vector<int> at(static_cast<std::size_t>(x.size()), 0);
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    at[static_cast<std::size_t>(j)] = x[j] == box.lower[j] ? -1 : x[j] == box.upper[j] ? 1 : 0;
  }
  return at;
}

/// The coordinates with activeBounds(x, box)[j] == side (0: free).
std::vector<Eigen::Index> sides(const Eigen::VectorXd& x, const Box& box, int side) {
  const std::vector<int> at = activeBounds(x, box);
  std::vector<Eigen::Index> js;
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    if (at[static_cast<std::size_t>(j)] == side) js.push_back(j);
  }
  return js;
}

/// b^T u - sum_j max(lower_j g_j, upper_j g_j), g = A^T u: a lower bound on the box optimum for
/// any |u_i| <= 1 (see the top of the file), accumulated in long double.
double boxBound(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Box& box,
                const Eigen::VectorXd& u) {
  const long double bu = lad_detail::dotLong(b, u);
  long double charge = 0.0L;
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    const long double g = lad_detail::columnDotLong(A, j, u);
    charge += std::max(static_cast<long double>(box.lower[j]) * g,
                       static_cast<long double>(box.upper[j]) * g);
  }
  return static_cast<double>(bu - charge);
}

struct Certificate {
  double bound = 0.0;
  Eigen::VectorXd u;
};

/// A^T u on the columns `cols`, accumulated in long double.
Eigen::VectorXd columnDot(const Eigen::MatrixXd& A, const std::vector<Eigen::Index>& cols,
                          const Eigen::VectorXd& u) {
  Eigen::VectorXd g(static_cast<Eigen::Index>(cols.size()));
  for (std::size_t k = 0; k < cols.size(); ++k) {
    long double sum = 0.0L;
    for (Eigen::Index i = 0; i < A.rows(); ++i) {
      sum += static_cast<long double>(A(i, cols[k])) * u[i];
    }
    g[static_cast<Eigen::Index>(k)] = static_cast<double>(sum);
  }
  return g;
}

/// The bound charges g_j = (A^T u)_j of a coordinate strictly inside the box at
/// max(lower_j g_j, upper_j g_j), so the roundoff left in an optimal dual's g_j (~eps sum_i
/// |A_ij|) costs ~eps ||A_j||_1 max(|lower_j|, |upper_j|): too much for a box far wider than x.
/// Two steps of the least-norm correction of the entries with |u_i| < kRoom (the rows x is fitted
/// through) that zeroes those g_j, with g in long double, cut it to the rounding of u itself.
Eigen::VectorXd refineDual(const Eigen::MatrixXd& A, const std::vector<Eigen::Index>& free,
                           Eigen::VectorXd u) {
  std::vector<Eigen::Index> inner;
  for (Eigen::Index i = 0; i < u.size(); ++i) {
    if (std::abs(u[i]) < kRoom) inner.push_back(i);
  }
  if (free.empty() || inner.size() < free.size()) return u;
  const auto n_free = static_cast<Eigen::Index>(free.size());
  Eigen::MatrixXd Mt(n_free, static_cast<Eigen::Index>(inner.size()));
  for (std::size_t k = 0; k < inner.size(); ++k) {
    for (std::size_t j = 0; j < free.size(); ++j) {
      Mt(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(k)) = A(inner[k], free[j]);
    }
  }
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(Mt);
  for (int step = 0; step < 2; ++step) {
    const Eigen::VectorXd delta = cod.solve(-columnDot(A, free, u));
    if (!delta.allFinite()) break;
    for (std::size_t k = 0; k < inner.size(); ++k) {
      double& v = u[inner[k]];
      v = std::clamp(v + delta[static_cast<Eigen::Index>(k)], -1.0, 1.0);
    }
  }
  return u;
}

/// The best of several duals: the solver's own (data rows, clipped to [-1, 1] against roundoff);
/// u_i = sign(r_i) at x, keeping the solver's u_i where r_i is at its roundoff level (the rows x
/// is fitted through, whose u_i carry the optimality conditions), which repairs a solver dual
/// shrunk to make its penalty-row entries feasible; and each of the two refined by refineDual on
/// the coordinates not on a bound. Every candidate is a valid bound; the highest is kept.
Certificate certify(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Box& box,
                    const Eigen::VectorXd& x, const Eigen::VectorXd& u_solver) {
  Certificate best{0.0, u_solver.cwiseMax(-1.0).cwiseMin(1.0)};
  best.bound = boxBound(A, b, box, best.u);
  const auto consider = [&](Eigen::VectorXd u) {
    const double bound = boxBound(A, b, box, u);
    if (bound > best.bound) best = Certificate{bound, std::move(u)};
  };
  const Eigen::VectorXd r = b - A * x;
  const Eigen::VectorXd scale = b.cwiseAbs() + A.cwiseAbs() * x.cwiseAbs();
  const double factor = 8.0 * static_cast<double>(A.cols() + 1) * kEpsilon;
  Eigen::VectorXd u(r.size());
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    u[i] = std::abs(r[i]) > factor * scale[i] ? (r[i] > 0.0 ? 1.0 : -1.0) : best.u[i];
  }
  const std::vector<Eigen::Index> free = sides(x, box, 0);
  const Eigen::VectorXd u_clipped = best.u;
  consider(refineDual(A, free, u));
  consider(std::move(u));
  consider(refineDual(A, free, u_clipped));
  return best;
}

std::string describeActive(const std::vector<int>& at) {
  std::string s;
  int count = 0;
  for (std::size_t j = 0; j < at.size(); ++j) {
    if (at[j] == 0) continue;
    s += (count++ ? ", x" : " (x") + core::toText(j) + (at[j] < 0 ? " at lower" : " at upper");
  }
  return core::toText(count) + " of " + core::toText(at.size()) + " bounds active" +
         (count ? s + ")" : "");
}

/// A point in the box, its cost, the best certificate found for it and how it was found.
struct Candidate {
  Eigen::VectorXd x;
  double cost = 0.0;
  Certificate cert;
  long iterations = 0;
  std::string message;  ///< the inner solver's message
};

Candidate candidate(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Box& box,
                    const Eigen::VectorXd& x, const Eigen::VectorXd& u_solver,
                    const LadResult& sol) {
  Candidate c;
  c.x = intoBox(A, b, box, x);
  c.cost = l1Cost(A, b, c.x);
  c.cert = certify(A, b, box, c.x, u_solver);
  c.iterations = sol.summary.iterations;
  c.message = sol.summary.message;
  return c;
}

/// Pass 1: the penalised problem (see the top of the file). Its cost carries the constant K, so
/// its relative tolerance must be tighter by max(1, cost) / max(1, cost + K) for the box gap (at
/// most the penalised gap) to meet ours; the cost is not known yet, and its lower bound 0 asks the
/// interior point to go to its rounding level (measured on knee-like data: one or two iterations
/// more than the plain tolerance takes). Empty when the penalised problem is rank deficient.
std::optional<Candidate> penaltyPass(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                                     const Box& box, const LadOptions& options,
                                     std::string& failure) {
  const Penalised pen = penalise(A, b, box);
  LadOptions inner = options;
  inner.gap_tolerance = std::max(options.gap_tolerance / (1.0 + pen.constant), kTiny);
  const LadResult sol = solveLeastAbsoluteDeviations(pen.A, pen.b, inner);
  if (sol.summary.status == Status::kRankDeficient) {
    failure = sol.summary.message;
    return std::nullopt;
  }
  return candidate(A, b, box, sol.x, sol.dual.head(A.rows()), sol);
}

/// Pass 2 helper: the bounds to hold in the next round of the active-set iteration. Those x sits
/// on, less those whose multiplier g_j = (A^T u)_j has the wrong sign (g_j > 0 on a lower bound or
/// g_j < 0 on an upper one: the cost falls moving inwards) by more than its roundoff level,
/// 8 (p + 1) eps ||A_j||_1 (a multiplier at that level is a degenerate zero, not a direction).
std::vector<int> nextActiveSet(const Eigen::MatrixXd& A, const Box& box, const Candidate& c) {
  std::vector<int> at = activeBounds(c.x, box);
  std::vector<Eigen::Index> held;
  for (std::size_t j = 0; j < at.size(); ++j) {
    if (at[j] != 0) held.push_back(static_cast<Eigen::Index>(j));
  }
  const Eigen::VectorXd g = columnDot(A, held, c.cert.u);
  const double factor = 8.0 * static_cast<double>(A.cols() + 1) * kEpsilon;
  for (std::size_t k = 0; k < held.size(); ++k) {
    int& side = at[static_cast<std::size_t>(held[k])];
    const double roundoff = factor * A.col(held[k]).lpNorm<1>();
    if (side * g[static_cast<Eigen::Index>(k)] < -roundoff) side = 0;
  }
  return at;
}

/// Pass 2 helper: the unconstrained problem in the coordinates with at[j] == 0, the others held at
/// their bounds. No penalty rows, so only the data's own rounding; the point is clamped into the
/// box and its dual is certified against the whole box, so a wrong active set only costs
/// tightness. Empty when every bound is held or the free columns are rank deficient.
std::optional<Candidate> solveHolding(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                                      const Box& box, const LadOptions& options,
                                      const std::vector<int>& at) {
  std::vector<Eigen::Index> free;
  Eigen::VectorXd x(A.cols());
  Eigen::VectorXd b_free = b;
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    const int side = at[static_cast<std::size_t>(j)];
    if (side == 0) {
      free.push_back(j);
    } else {
      x[j] = side < 0 ? box.lower[j] : box.upper[j];
      b_free.noalias() -= x[j] * A.col(j);
    }
  }
  if (free.empty()) return std::nullopt;
  Eigen::MatrixXd A_free(A.rows(), static_cast<Eigen::Index>(free.size()));
  for (std::size_t k = 0; k < free.size(); ++k) {
    A_free.col(static_cast<Eigen::Index>(k)) = A.col(free[k]);
  }
  const LadResult sol = solveLeastAbsoluteDeviations(A_free, b_free, options);
  if (sol.summary.status == Status::kRankDeficient) return std::nullopt;
  for (std::size_t k = 0; k < free.size(); ++k) x[free[k]] = sol.x[static_cast<Eigen::Index>(k)];
  return candidate(A, b, box, x, sol.dual, sol);
}

/// The lower-cost point with the higher bound: each bound holds for the same box optimum.
Candidate merge(Candidate a, const Candidate& b) {
  Candidate best = a.cost <= b.cost ? a : b;
  best.cert = a.cert.bound >= b.cert.bound ? std::move(a.cert) : b.cert;
  best.iterations = a.iterations + b.iterations;
  best.message = a.message + "; then holding bounds: " + b.message;
  return best;
}

/// Pass 2, only when pass 1 is not certified: the penalty rows' right-hand sides carry rounding
/// errors of eps c_j max(|lower_j|, |upper_j|), which for a box far wider than |x| swamp the
/// differences in the data cost. An active-set iteration without them: hold the bounds the last
/// point sits on (less the wrongly signed), solve for the rest, repeat while not certified, at
/// most p + 1 rounds and never the same set twice.
Candidate activeSetPass(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Box& box,
                        const LadOptions& options, Candidate best,
                        const std::function<bool(const Candidate&)>& certified) {
  std::vector<std::vector<int>> tried;
  Candidate last = best;
  for (Eigen::Index round = 0; round <= A.cols() && !certified(best); ++round) {
    std::vector<int> held = nextActiveSet(A, box, last);
    if (std::find(tried.begin(), tried.end(), held) != tried.end()) break;
    std::optional<Candidate> next = solveHolding(A, b, box, options, held);
    if (!next) break;
    tried.push_back(std::move(held));
    best = merge(std::move(best), *next);
    last = std::move(*next);
  }
  return best;
}

}  // namespace

int BoxedLadResult::activeBounds() const {
  return static_cast<int>(
      std::count_if(at_bound.begin(), at_bound.end(), [](int side) { return side != 0; }));
}

BoxedLadResult solveBoxedLeastAbsoluteDeviations(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                                                 const Box& box, const LadOptions& options) {
  options.validate();
  checkInputs(A, b, box);
  const Stopwatch clock;
  const auto allowed = [&](const Candidate& c) {
    return std::max(options.gap_tolerance * std::max(1.0, std::abs(c.cost)),
                    roundingLevel(A, b, c.x));
  };
  const auto certified = [&](const Candidate& c) { return c.cost - c.cert.bound <= allowed(c); };

  std::string failure;
  std::optional<Candidate> best = penaltyPass(A, b, box, options, failure);
  if (!best) {
    // Cannot happen for a finite box (the penalty rows hold a scaled identity); kept honest:
    // the box point nearest 0 and the trivially feasible dual u = 0.
    best = candidate(A, b, box, Eigen::VectorXd::Zero(A.cols()), Eigen::VectorXd::Zero(A.rows()),
                     LadResult{});
  } else {
    best = activeSetPass(A, b, box, options, std::move(*best), certified);
  }

  const double limit = allowed(*best);  // before best->x moves out
  BoxedLadResult result;
  result.x = std::move(best->x);
  result.cost = best->cost;
  // Weak duality makes cost >= bound; a difference below zero is rounding and is reported as 0.
  result.dual_bound = std::min(best->cert.bound, result.cost);
  result.dual = std::move(best->cert.u);
  result.gap = result.cost - result.dual_bound;
  result.at_bound = activeBounds(result.x, box);
  const bool converged = result.gap <= limit;
  Summary& summary = result.summary;
  summary.status = !failure.empty() ? Status::kRankDeficient
                   : converged      ? Status::kConverged
                                    : Status::kMaxIterations;
  summary.message = (failure.empty() ? std::string() : "penalised problem: " + failure + "; ") +
                    (converged ? "converged" : "stopped") + " after " +
                    core::toText(best->iterations) + " interior-point iterations; gap " +
                    core::formatNumber(result.gap, 10) + (converged ? " <= " : " > ") + core::formatNumber(limit, 10) + "; " +
                    describeActive(result.at_bound) +
                    (best->message.empty() ? std::string() : " [" + best->message + "]");
  summary.iterations = best->iterations;
  summary.initial_cost = l1Cost(A, b, 0.5 * (box.lower + box.upper));
  summary.final_cost = result.cost;
  summary.wall_time_s = clock.seconds();
  return result;
}

}  // namespace exoid::ident
