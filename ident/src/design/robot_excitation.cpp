#include "exoid/ident/design/robot_excitation.hpp"

#include "exoid/core/format.hpp"
#include "exoid/core/random.hpp"
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/model/newton_euler.hpp"

#include <Eigen/Cholesky>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace exoid::ident {

namespace {
constexpr double kTwoPi = 6.283185307179586;
}

void ChainExcitationLimits::validate(int dof) const {
  for (const Eigen::VectorXd* v : {&q_min_rad, &q_max_rad, &qd_max_radps, &qdd_max_radps2, &tau_max_Nm}) {
    if (v->size() != dof) throw std::invalid_argument("excitation limits: one entry per joint (" + core::toText(dof) + ") expected");
  }
  for (int j = 0; j < dof; ++j) {
    if (!(q_min_rad[j] < q_max_rad[j])) throw std::invalid_argument("excitation limits: joint " + core::toText(j) + "'s range is empty");
    if (!(qd_max_radps[j] > 0.0 && qdd_max_radps2[j] > 0.0 && tau_max_Nm[j] > 0.0)) {
      throw std::invalid_argument("excitation limits: joint " + core::toText(j) + "'s speed, acceleration and torque limits must be > 0");
    }
  }
}

namespace {

// One period's sample times and each harmonic's cosine and sine there, computed once for the
// thousands of trajectories a design rates (the trigonometry was a tenth of its time).
struct PeriodGrid {
  double f0_hz = 0.0;
  Eigen::VectorXd w;     ///< per harmonic, rad/s
  Eigen::MatrixXd c, s;  ///< samples x harmonics
  PeriodGrid(double f0, int harmonics, int samples) : f0_hz(f0), w(harmonics), c(samples, harmonics), s(samples, harmonics) {
    for (int k = 1; k <= harmonics; ++k) w[k - 1] = kTwoPi * f0 * k;
    for (int i = 0; i < samples; ++i) {
      const double t_s = static_cast<double>(i) / (f0 * samples);
      for (int k = 1; k <= harmonics; ++k) {
        c(i, k - 1) = std::cos(w[k - 1] * t_s);
        s(i, k - 1) = std::sin(w[k - 1] * t_s);
      }
    }
  }
  int samples() const { return static_cast<int>(c.rows()); }
  void at(const core::FourierSeries& t, int i, Eigen::VectorXd& q, Eigen::VectorXd& qd, Eigen::VectorXd& qdd) const {
    q = t.offset_rad;
    qd.setZero(t.dof());
    qdd.setZero(t.dof());
    for (int k = 1; k <= t.harmonics(); ++k) t.addHarmonic(k, w[k - 1], c(i, k - 1), s(i, k - 1), q, qd, qdd);
  }
};

// What a rating needs: the limits alone (a feasibility check), the CRB criterion, or everything
// (the condition number too: a QR and an SVD the CRB criterion does not use).
enum class Rating { kLimits, kCrb, kFull };

ChainExcitationScore scoreOnGrid(const ChainModel& model, const BaseParameters& base, const core::FourierSeries& t,
                                 const Eigen::VectorXd& phi_nominal, const ChainExcitationLimits& limits, const PeriodGrid& grid,
                                 Rating rating) {
  const int dof = model.dof();
  const int samples = grid.samples();
  const Eigen::Index p = model.standardParameterCount();
  Eigen::MatrixXd W(static_cast<Eigen::Index>(samples) * dof, p);
  ChainRegressorWorkspace work;
  Eigen::VectorXd q, qd, qdd;
  Eigen::VectorXd tau(dof);
  ChainExcitationScore s;
  const std::vector<std::string> names = model.jointNames();
  const auto violate = [&](double value, double limit, const char* what, int j) {
    const double excess = (std::abs(value) - limit) / limit;
    if (excess > s.worst_violation) {
      s.worst_violation = excess;
      s.worst_violation_name = std::string(what) + "[" + names[static_cast<std::size_t>(j)] + "]";
    }
  };
  const ChainBaseMotion still = ChainBaseMotion::still(model);
  for (int i = 0; i < samples; ++i) {
    grid.at(t, i, q, qd, qdd);
    chainRegressorInto(model, q, qd, qdd, still, work, W.middleRows(static_cast<Eigen::Index>(i) * dof, dof));
    tau.noalias() = W.middleRows(static_cast<Eigen::Index>(i) * dof, dof) * phi_nominal;
    for (int j = 0; j < dof; ++j) {
      const double span = std::isfinite(limits.q_max_rad[j] - limits.q_min_rad[j]) ? limits.q_max_rad[j] - limits.q_min_rad[j] : 1.0;
      if (q[j] > limits.q_max_rad[j]) violate(span + (q[j] - limits.q_max_rad[j]), span, "q_max", j);
      if (q[j] < limits.q_min_rad[j]) violate(span + (limits.q_min_rad[j] - q[j]), span, "q_min", j);
      violate(qd[j], limits.qd_max_radps[j], "qd", j);
      violate(qdd[j], limits.qdd_max_radps2[j], "qdd", j);
      violate(tau[j], limits.tau_max_Nm[j], "tau", j);
    }
  }
  if (rating == Rating::kLimits) return s;
  Eigen::MatrixXd Wb = base.baseRegressor(W);
  const Eigen::VectorXd norms = Wb.colwise().norm().transpose();
  if (rating == Rating::kFull) s.condition_number = scaledConditionNumber(Wb);
  // Cramer-Rao stds with unit noise per row: sqrt of diag((Wb' Wb)^-1), through the scaled
  // columns' Cholesky (their Gram matrix is well scaled); a singular one scores +infinity.
  for (Eigen::Index c = 0; c < Wb.cols(); ++c) Wb.col(c) /= std::max(norms[c], 1e-300);
  Eigen::LLT<Eigen::MatrixXd> llt(Wb.transpose() * Wb);
  if (llt.info() != Eigen::Success || (rating == Rating::kFull && !std::isfinite(s.condition_number))) {
    s.sum_log_std = std::numeric_limits<double>::infinity();
    return s;
  }
  const Eigen::MatrixXd inv = llt.solve(Eigen::MatrixXd::Identity(Wb.cols(), Wb.cols()));
  for (Eigen::Index c = 0; c < Wb.cols(); ++c) s.sum_log_std += 0.5 * std::log(inv(c, c)) - std::log(std::max(norms[c], 1e-300));
  if (!std::isfinite(s.sum_log_std)) s.sum_log_std = std::numeric_limits<double>::infinity();  // numerically singular
  return s;
}

}  // namespace

ChainExcitationScore scoreChainExcitation(const ChainModel& model, const BaseParameters& base, const core::FourierSeries& t,
                                          const Eigen::VectorXd& phi_nominal, const ChainExcitationLimits& limits, int samples) {
  return scoreOnGrid(model, base, t, phi_nominal, limits, PeriodGrid(t.f0_hz, t.harmonics(), samples), Rating::kFull);
}

namespace {

// Free coefficients per joint: offset, a_2..a_N, b_2..b_N; a_1, b_1 put the joint at rest at t = 0.
core::FourierSeries fromFree(const ExcitationOptions& o, int dof, const Eigen::VectorXd& p) {
  const int n = o.harmonics;
  core::FourierSeries t = core::FourierSeries::still(dof, n, o.f0_hz);
  int at = 0;
  for (int j = 0; j < dof; ++j) {
    t.offset_rad[j] = p[at++];
    at = unpackRestingHarmonics(p, at, t.a_rad.col(j), t.b_rad.col(j));
  }
  return t;
}

}  // namespace

ChainExcitationDesign designChainExcitation(const ExcitationOptions& o, const ChainModel& model, const BaseParameters& base,
                                            const Eigen::VectorXd& phi_nominal, const ChainExcitationLimits& limits) {
  o.validate();
  model.validate();
  const int dof = model.dof();
  limits.validate(dof);
  if (o.hip_locked) throw std::invalid_argument("chain excitation: no joint is locked in a chain's design (hip_locked must be false)");
  if (phi_nominal.size() != model.standardParameterCount()) throw std::invalid_argument("chain excitation: phi_nominal has the wrong size");
  const int per_joint = 2 * o.harmonics - 1, dim = dof * per_joint;
  const PeriodGrid coarse(o.f0_hz, o.harmonics, o.samples), fine(o.f0_hz, o.harmonics, 1000);
  const auto score = [&](const core::FourierSeries& t, const PeriodGrid& grid, Rating rating) {
    return scoreOnGrid(model, base, t, phi_nominal, limits, grid, rating);
  };
  const Rating criterion = o.criterion == ExcitationCriterion::kCrb ? Rating::kCrb : Rating::kFull;
  const auto objective = [&](const Eigen::VectorXd& p) {
    const ChainExcitationScore s = score(fromFree(o, dof, p), coarse, criterion);
    const double f = o.criterion == ExcitationCriterion::kCrb ? s.sum_log_std : std::log(s.condition_number);
    return f + 1e5 * s.worst_violation * s.worst_violation;
  };
  ChainExcitationDesign d;
  const RestartSearch found = searchFromRestarts(
      o,
      [&](core::Rng& rng) {
        // About the middle of each joint's range (0 without one), small decaying harmonics.
        Eigen::VectorXd p(dim);
        int at = 0;
        for (int j = 0; j < dof; ++j) {
          const bool ranged = std::isfinite(limits.q_min_rad[j]) && std::isfinite(limits.q_max_rad[j]);
          const double mid = ranged ? 0.5 * (limits.q_min_rad[j] + limits.q_max_rad[j]) : 0.0;
          const double half = ranged ? 0.5 * (limits.q_max_rad[j] - limits.q_min_rad[j]) : 1.0;
          p[at++] = mid + 0.25 * half * rng.uniform(-1.0, 1.0);
          for (int k = 0; k < 2 * (o.harmonics - 1); ++k) p[at++] = 0.15 * half * rng.uniform(-1.0, 1.0) / (1 + k % (o.harmonics - 1));
        }
        return p;
      },
      objective, [&](const Eigen::VectorXd& p) { return score(fromFree(o, dof, p), coarse, Rating::kLimits).worst_violation == 0.0; });
  d.evaluations = found.evaluations;
  d.feasible_restarts = found.feasible_restarts;
  core::FourierSeries t = fromFree(o, dof, found.x);
  // Peaks between the optimiser's samples, or no feasible end point: shrink the harmonics.
  const auto shrunk = [&t](double s) {
    core::FourierSeries r = t;
    r.a_rad *= s;
    r.b_rad *= s;
    return r;
  };
  if (score(t, fine, Rating::kLimits).worst_violation > 0.0) {
    t = shrunk(largestFeasibleScale([&](double s) { return !(score(shrunk(s), fine, Rating::kLimits).worst_violation > 0.0); }));
  }
  d.trajectory = t;
  d.score = score(t, fine, Rating::kFull);
  return d;
}

}  // namespace exoid::ident
