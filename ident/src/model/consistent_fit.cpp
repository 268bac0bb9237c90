#include "exoid/ident/model/consistent_fit.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/model/log_cholesky.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <array>
#include <cmath>
#include <stdexcept>

namespace exoid::ident {

void ConsistentFitOptions::validate() const {
  if (max_iterations < 1) throw std::invalid_argument("consistent fit: 'max_iterations' must be >= 1, got " + core::toText(max_iterations));
  if (!(tolerance > 0.0 && tolerance <= 1e-3)) throw std::invalid_argument("consistent fit: 'tolerance' must be in (0, 1e-3], got " + core::toText(tolerance));
  if (!(barrier_gap > 0.0 && barrier_gap <= 1e-3)) throw std::invalid_argument("consistent fit: 'barrier_gap' must be in (0, 1e-3], got " + core::toText(barrier_gap));
  if (!(max_link_mass_kg > 0.0 && std::isfinite(max_link_mass_kg))) throw std::invalid_argument("consistent fit: 'max_link_mass_kg' must be a positive number, got " + core::toText(max_link_mass_kg));
  if (!(link_radius_m > 0.0 && std::isfinite(link_radius_m))) throw std::invalid_argument("consistent fit: 'link_radius_m' must be a positive number, got " + core::toText(link_radius_m));
  if (max_newton_steps < 1) throw std::invalid_argument("consistent fit: 'max_newton_steps' must be >= 1, got " + core::toText(max_newton_steps));
}

const char* toString(ConsistentFitStatus s) {
  switch (s) {
    case ConsistentFitStatus::kLeastSquaresConsistent: return "least_squares_consistent";
    case ConsistentFitStatus::kConstrained: return "constrained";
    case ConsistentFitStatus::kMaxIterations: return "max_iterations";
  }
  return "?";
}

namespace {

// theta: per joint its link's 10 log-Cholesky coordinates, then z for each friction coefficient
// and armature (coefficient = z^2, so zero is reachable), in the standard layout's order.
struct Coordinates {
  const ChainModel& model;
  std::vector<JointParameterLayout> layout;

  Eigen::VectorXd toPhi(const Eigen::VectorXd& theta) const {
    Eigen::VectorXd phi(theta.size());
    for (const JointParameterLayout& l : layout) phi.segment<kLinkParams>(l.link) = linkFromLogCholesky(theta.segment<kLinkParams>(l.link));
    for (Eigen::Index k = 0; k < theta.size(); ++k) {
      if (!isLinkColumn(k)) phi[k] = theta[k] * theta[k];
    }
    return phi;
  }

  Eigen::MatrixXd jacobian(const Eigen::VectorXd& theta) const {
    Eigen::MatrixXd D = Eigen::MatrixXd::Zero(theta.size(), theta.size());
    for (const JointParameterLayout& l : layout) {
      D.block<kLinkParams, kLinkParams>(l.link, l.link) = linkFromLogCholeskyJacobian(theta.segment<kLinkParams>(l.link));
    }
    for (Eigen::Index k = 0; k < theta.size(); ++k) {
      if (!isLinkColumn(k)) D(k, k) = 2.0 * theta[k];
    }
    return D;
  }

  Eigen::VectorXd start(const Eigen::VectorXd& phi_start) const {
    Eigen::VectorXd theta(phi_start.size());
    for (const JointParameterLayout& l : layout) {
      LinkVector phi = phi_start.segment<kLinkParams>(l.link);
      if (!(pseudoInertiaMinEigenvalue(phi) > 1e-9)) {
        phi.setZero();
        phi << 1.0, 0.0, 0.0, 0.0, 0.01, 0.0, 0.0, 0.01, 0.0, 0.01;  // 1 kg, COM at the origin
      }
      theta.segment<kLinkParams>(l.link) = logCholeskyFromLink(phi);
    }
    for (Eigen::Index k = 0; k < theta.size(); ++k) {
      if (!isLinkColumn(k)) theta[k] = phi_start[k] > 1e-6 ? std::sqrt(phi_start[k]) : 1.0;
    }
    return theta;
  }

  bool isLinkColumn(Eigen::Index k) const {
    for (const JointParameterLayout& l : layout) {
      if (k >= l.link && k < l.link + kLinkParams) return true;
    }
    return false;
  }
};

// The constrained optimum by a log-barrier interior point in standard-parameter space, from a
// strictly feasible phi: minimise t q(phi) + B(phi) for growing t (Newton, backtracking inside the
// set), q the excess cost scaled by 1 / scale and, per link k and coefficient j,
//   B = sum_k [-log det J_k - log(M - m_k) - log(R^2 m_k - tr Sigma_k)] - sum_j log f_j.
// The two bounds (mass at most M, the mass within a sphere of radius R about the link's origin:
// Wensing, Kim and Slotine's bounding-volume condition) make the set compact: without them the
// barrier is unbounded below along what no torque shows (an unidentified mass growing without
// bound lowers -log det J for ever). The barrier's parameter is 6 per link and 1 per
// coefficient, so at the end of a centring q is within nu / t of its minimum over the set.
class BarrierSolver {
 public:
  // q(phi) = ||RC phi - target||^2 / scale, evaluated from the residual: the excess is a tiny
  // fraction of scale near a boundary optimum, and a quadratic with its constant dropped would
  // lose it to rounding once t is large.
  BarrierSolver(const Coordinates& coords, const Eigen::MatrixXd& RC, const Eigen::VectorXd& target, double scale, double max_mass_kg,
                double radius_m)
      : coords_(coords), RC_(RC), target_(target), scale_(scale), Q2_(2.0 / scale * RC.transpose() * RC), max_mass_(max_mass_kg) {
    for (int i = 0; i < kLinkParams; ++i) E_[static_cast<std::size_t>(i)] = pseudoInertia(LinkVector::Unit(i));
    // R^2 m - tr Sigma, tr Sigma = (Ixx + Iyy + Izz) / 2 about the origin.
    sphere_.setZero();
    sphere_ << radius_m * radius_m, 0.0, 0.0, 0.0, -0.5, 0.0, 0.0, -0.5, 0.0, -0.5;
    for (Eigen::Index k = 0; k < RC.cols(); ++k) {
      if (!coords_.isLinkColumn(k)) coefficients_.push_back(k);
    }
    barrier_parameter_ = 6.0 * static_cast<double>(coords_.layout.size()) + static_cast<double>(coefficients_.size());
  }

  double objective(const Eigen::VectorXd& phi) const { return (RC_ * phi - target_).squaredNorm() / scale_; }

  bool feasible(const Eigen::VectorXd& phi) const {
    for (const JointParameterLayout& l : coords_.layout) {
      const LinkVector link = phi.segment<kLinkParams>(l.link);
      if (!(link[0] < max_mass_) || !(sphere_.dot(link) > 0.0)) return false;
      Eigen::LLT<Eigen::Matrix4d> llt(pseudoInertia(link));
      if (llt.info() != Eigen::Success) return false;
    }
    for (Eigen::Index k : coefficients_) {
      if (!(phi[k] > 0.0)) return false;
    }
    return true;
  }

  struct Solve {
    int newton_steps = 0;
    /// nu / t of the last centring that reached its centre (0: none did): the optimum's excess is
    /// within it of phi's (in units of scale); rounding that stalls a later centring leaves it there.
    double gap_bound = 0.0;
    bool converged = false;  ///< the gap bound met the stopping rule (else rounding or the budget stopped it)
  };

  // Newton centring at t, then t x 10, until the gap bound nu / t is below gap times the residual
  // sum of squares (floor: the unconstrained one, ls_cost in units of scale).
  Solve solve(Eigen::VectorXd& phi, double gap, double ls_cost, int max_newton) const {
    double t = barrier_parameter_ / std::max(objective(phi), 1e-6);
    Solve out;  // gap_bound 0 until a centring completes: no claim
    bool stalled = false;
    while (out.newton_steps < max_newton && !stalled) {
      bool centred = false;
      out.newton_steps += centre(phi, t, max_newton - out.newton_steps, centred, stalled);
      if (centred) out.gap_bound = barrier_parameter_ / t;
      if (centred && barrier_parameter_ / t <= gap * (objective(phi) + ls_cost)) {
        out.converged = true;
        break;
      }
      t *= 10.0;
    }
    return out;
  }

  // The barrier's change from a feasible phi to a feasible trial (t q included): q's change from
  // the residual r and the step's image d, (2 r.d + d.d) / scale, not as a difference of two
  // values of t q (at a large t their rounding, 1e-16 t q, exceeds the change a Newton step makes:
  // the line search would stall short of the gap the stopping rule promises).
  double change(const Eigen::VectorXd& phi, const Eigen::VectorXd& trial, double t) const {
    const Eigen::VectorXd r = RC_ * phi - target_, d = RC_ * (trial - phi);
    return t * (2.0 * r.dot(d) + d.squaredNorm()) / scale_ + barrierTerms(trial) - barrierTerms(phi);
  }

  // The barrier's own terms (without t q) at a feasible phi.
  double barrierTerms(const Eigen::VectorXd& phi) const {
    double v = 0.0;
    for (const JointParameterLayout& l : coords_.layout) {
      const LinkVector link = phi.segment<kLinkParams>(l.link);
      Eigen::LLT<Eigen::Matrix4d> llt(pseudoInertia(link));
      const Eigen::Matrix4d L = llt.matrixL();
      v -= 2.0 * L.diagonal().array().log().sum() + std::log(max_mass_ - link[0]) + std::log(sphere_.dot(link));
    }
    for (Eigen::Index k : coefficients_) v -= std::log(phi[k]);
    return v;
  }

  // The barrier's gradient and Hessian at a feasible phi (t q included).
  void derivatives(const Eigen::VectorXd& phi, double t, Eigen::VectorXd& g, Eigen::MatrixXd& H) const {
    g = (2.0 * t / scale_) * (RC_.transpose() * (RC_ * phi - target_));
    H = t * Q2_;
    for (const JointParameterLayout& l : coords_.layout) {
      const LinkVector link = phi.segment<kLinkParams>(l.link);
      const Eigen::Matrix4d Jinv = pseudoInertia(link).inverse();
      std::array<Eigen::Matrix4d, kLinkParams> B;
      for (std::size_t i = 0; i < B.size(); ++i) {
        B[i] = Jinv * E_[i];
        g[l.link + static_cast<Eigen::Index>(i)] -= B[i].trace();
      }
      for (std::size_t i = 0; i < B.size(); ++i) {
        for (std::size_t j = 0; j <= i; ++j) {
          const double h = (B[i].array() * B[j].transpose().array()).sum();
          const auto a = l.link + static_cast<Eigen::Index>(i), b = l.link + static_cast<Eigen::Index>(j);
          H(a, b) += h;
          if (i != j) H(b, a) += h;
        }
      }
      const double slack_mass = max_mass_ - link[0], slack_sphere = sphere_.dot(link);
      g[l.link] += 1.0 / slack_mass;
      H(l.link, l.link) += 1.0 / (slack_mass * slack_mass);
      g.segment<kLinkParams>(l.link) -= sphere_ / slack_sphere;
      H.block<kLinkParams, kLinkParams>(l.link, l.link) += sphere_ * sphere_.transpose() / (slack_sphere * slack_sphere);
    }
    for (Eigen::Index k : coefficients_) {
      g[k] -= 1.0 / phi[k];
      H(k, k) += 1.0 / (phi[k] * phi[k]);
    }
  }

 private:
  // Newton steps at t until the decrement says the centre is reached (centred); stalled when
  // rounding stops the line search first (the problem's conditioning at this t: a larger t cannot
  // do better); neither when the budget runs out.
  // The search halves the step down to 1e-12: next to the boundary a feasible step can be that
  // short, and stopping at 1e-6 left the last centring (and the gap it promises) undone.
  int centre(Eigen::VectorXd& phi, double t, int max_newton, bool& centred, bool& stalled) const {
    Eigen::VectorXd g;
    Eigen::MatrixXd H;
    for (int it = 0; it < max_newton; ++it) {
      derivatives(phi, t, g, H);
      // Jacobi-scaled: near the boundary the barrier's curvature spans many decades (a mass of
      // 1e-8 kg beside one of 1e3 kg), which an unscaled factorisation loses to rounding.
      const Eigen::VectorXd d = H.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
      const Eigen::MatrixXd Hs = d.asDiagonal() * H * d.asDiagonal();
      const Eigen::VectorXd step = d.cwiseProduct(Hs.ldlt().solve(-d.cwiseProduct(g)));
      const double decrement = -g.dot(step);  // Newton decrement squared
      if (!(decrement > 1e-9)) {  // within 1e-9 / 2 of the centre: rounding beyond
        centred = true;
        return it + 1;
      }
      double s = 1.0;
      while (s > 1e-12) {
        const Eigen::VectorXd trial = phi + s * step;
        if (feasible(trial) && change(phi, trial, t) <= -0.25 * s * decrement) break;
        s *= 0.5;
      }
      if (s <= 1e-12) {
        stalled = true;
        return it + 1;
      }
      phi += s * step;
    }
    return max_newton;
  }

  const Coordinates& coords_;
  const Eigen::MatrixXd& RC_;
  const Eigen::VectorXd& target_;
  double scale_;
  Eigen::MatrixXd Q2_;
  double max_mass_;
  LinkVector sphere_;
  std::array<Eigen::Matrix4d, kLinkParams> E_;
  std::vector<Eigen::Index> coefficients_;
  double barrier_parameter_ = 0.0;
};

void checkNormalEquations(const ChainModel& model, const BaseParameters& base, const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                          const Eigen::VectorXd& phi_start) {
  const Eigen::Index p = model.standardParameterCount(), r = base.rank;
  if (A.rows() != r || A.cols() != r || b.size() != r || phi_start.size() != p) {
    throw std::invalid_argument("consistent fit: expected A " + core::toText(r) + " x " + core::toText(r) + ", b of " +
                                core::toText(r) + " and phi_start of " + core::toText(p) + " entries");
  }
  if (!A.allFinite() || !b.allFinite() || !phi_start.allFinite()) throw std::invalid_argument("consistent fit: a NaN or Inf in the data");
}

// Levenberg-Marquardt on ||RC phi(theta) - target||^2 from theta: until the cost is within
// tolerance of LS (LS is consistent), no damped step decreases it by more than that (the optimum
// is constrained), or max_iterations.
struct LmFit {
  Eigen::VectorXd theta;
  double cost = 0.0;
  int iterations = 0;
  ConsistentFitStatus status = ConsistentFitStatus::kMaxIterations;
};

LmFit levenbergMarquardt(const Coordinates& coords, const Eigen::MatrixXd& RC, const Eigen::VectorXd& target, double scale,
                         Eigen::VectorXd theta, const ConsistentFitOptions& options) {
  LmFit out;
  Eigen::VectorXd residual = RC * coords.toPhi(theta) - target;
  double cost = residual.squaredNorm();
  double lambda = 1e-3;
  for (int it = 0; it < options.max_iterations; ++it) {
    out.iterations = it + 1;
    if (cost <= options.tolerance * scale) {
      out.status = ConsistentFitStatus::kLeastSquaresConsistent;
      break;
    }
    const Eigen::MatrixXd Jr = RC * coords.jacobian(theta);
    const Eigen::MatrixXd JtJ = Jr.transpose() * Jr;
    const Eigen::VectorXd g = Jr.transpose() * residual;
    const double diag_scale = std::max(JtJ.diagonal().maxCoeff(), 1e-300);
    bool accepted = false;
    double decrease = 0.0;
    for (int tries = 0; tries < 40 && !accepted; ++tries) {
      Eigen::MatrixXd M = JtJ;
      M.diagonal().array() += lambda * diag_scale;
      const Eigen::VectorXd step = M.ldlt().solve(-g);
      const Eigen::VectorXd trial = theta + step;
      const Eigen::VectorXd trial_residual = RC * coords.toPhi(trial) - target;
      const double trial_cost = trial_residual.squaredNorm();
      if (std::isfinite(trial_cost) && trial_cost < cost) {
        decrease = cost - trial_cost;
        theta = trial;
        residual = trial_residual;
        cost = trial_cost;
        lambda = std::max(lambda / 3.0, 1e-12);
        accepted = true;
      } else {
        lambda *= 4.0;
      }
    }
    if (!accepted || decrease <= options.tolerance * scale) {
      out.status = cost <= options.tolerance * scale ? ConsistentFitStatus::kLeastSquaresConsistent : ConsistentFitStatus::kConstrained;
      break;
    }
  }
  out.theta = theta;
  out.cost = cost;
  return out;
}

// The optimum on the boundary (or LS needs a link beyond the bounds): the barrier, from the
// start's (consistent) bodies. Not from LM's point: LM crawls towards the boundary, and a barrier
// started next to it needs hundreds of damped Newton steps to get away (measured). Sets fit.phi,
// its status and steps; returns its excess cost over LS and the barrier's gap bound, in the same
// units: an excess within it does not tell LS from a boundary optimum.
struct BoundaryFit {
  double excess = 0.0, gap_bound = 0.0;
  bool converged = false;
};

BoundaryFit fitOnBoundary(ConsistentFit& fit, const Coordinates& coords, const BarrierSolver& barrier, const BaseParameters& base,
                     const Eigen::MatrixXd& A, const Eigen::VectorXd& phi_start, double scale, const ConsistentFitOptions& options) {
  Eigen::VectorXd phi = coords.toPhi(coords.start(phi_start));
  if (!barrier.feasible(phi)) phi = coords.toPhi(coords.start(Eigen::VectorXd::Zero(phi.size())));
  const BarrierSolver::Solve solved = barrier.solve(phi, options.barrier_gap, fit.ls_cost / scale, options.max_newton_steps);
  fit.barrier_newton_steps = solved.newton_steps;
  fit.phi = phi;
  fit.status = ConsistentFitStatus::kConstrained;
  const Eigen::VectorXd d = base.combination * fit.phi - fit.beta_ls;
  return {d.dot(A * d), solved.gap_bound * scale, solved.converged};
}

std::string fitMessage(const ConsistentFit& fit) {
  return std::string(toString(fit.status)) + " after " + core::toText(fit.iterations) + " Levenberg-Marquardt iterations" +
         (fit.barrier_newton_steps ? " and " + core::toText(fit.barrier_newton_steps) + " barrier Newton steps" : std::string()) +
         "; consistency costs " + core::formatNumber(fit.excess_cost, 4) + " of the residual sum of squares " +
         core::formatNumber(fit.ls_cost, 6);
}

}  // namespace

ConsistentFit consistentFitNormal(const ChainModel& model, const BaseParameters& base, const Eigen::MatrixXd& A,
                                  const Eigen::VectorXd& b, double yy, const Eigen::VectorXd& phi_start,
                                  const ConsistentFitOptions& options) {
  options.validate();
  checkNormalEquations(model, base, A, b, phi_start);
  Eigen::LLT<Eigen::MatrixXd> llt(A);
  if (llt.info() != Eigen::Success) {
    throw std::invalid_argument("consistent fit: the base regressor is not of full rank: the record does not identify every base parameter");
  }
  ConsistentFit fit;
  fit.beta_ls = llt.solve(b);
  fit.ls_cost = std::max(0.0, yy - b.dot(fit.beta_ls));
  const Eigen::MatrixXd R = llt.matrixU();  // A = R' R
  const Eigen::MatrixXd RC = R * base.combination;
  const Eigen::VectorXd target = R * fit.beta_ls;
  const double scale = target.squaredNorm();
  const Coordinates coords{model, model.layout()};

  const LmFit lm = levenbergMarquardt(coords, RC, target, scale, coords.start(phi_start), options);
  fit.iterations = lm.iterations;
  fit.status = lm.status;
  double cost = lm.cost;
  fit.phi = coords.toPhi(lm.theta);
  const BarrierSolver barrier(coords, RC, target, scale, options.max_link_mass_kg, options.link_radius_m);
  const bool interior_optimum = fit.status == ConsistentFitStatus::kLeastSquaresConsistent && barrier.feasible(fit.phi);
  if (!interior_optimum) {
    const BoundaryFit boundary = fitOnBoundary(fit, coords, barrier, base, A, phi_start, scale, options);
    cost = boundary.excess;
    // LM stops early on an ill-conditioned A (a step's decrease below the tolerance before the
    // excess is). LS is consistent all the same when the barrier meets it to the tolerance, or when
    // rounding or the budget stopped the barrier (exact data: their standard errors are rounding)
    // with an excess within the gap bound it proved: nothing then tells LS from the optimum.
    if (cost <= options.tolerance * scale || (!boundary.converged && cost <= boundary.gap_bound)) {
      fit.status = ConsistentFitStatus::kLeastSquaresConsistent;
    }
  }
  fit.beta = base.combination * fit.phi;
  fit.excess_cost = cost;
  for (const JointParameterLayout& l : coords.layout) fit.link_min_eigenvalue.push_back(pseudoInertiaMinEigenvalue(fit.phi.segment<kLinkParams>(l.link)));
  fit.message = fitMessage(fit);
  return fit;
}

ConsistentFit consistentFit(const ChainModel& model, const BaseParameters& base, const Eigen::MatrixXd& W,
                            const Eigen::VectorXd& y, const Eigen::VectorXd& phi_start, const ConsistentFitOptions& options) {
  if (W.cols() != model.standardParameterCount() || W.rows() != y.size()) {
    throw std::invalid_argument("consistent fit: expected W with " + core::toText(model.standardParameterCount()) +
                                " columns and as many rows as y (" + core::toText(static_cast<long long>(y.size())) + ")");
  }
  if (!W.allFinite() || !y.allFinite()) throw std::invalid_argument("consistent fit: a NaN or Inf in the data");
  const Eigen::MatrixXd Wb = base.baseRegressor(W);
  return consistentFitNormal(model, base, Wb.transpose() * Wb, Wb.transpose() * y, y.squaredNorm(), phi_start, options);
}

}  // namespace exoid::ident
