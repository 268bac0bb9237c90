#include "exoid/ident/design/excitation.hpp"

#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/estimators/nelder_mead.hpp"
#include "exoid/core/random.hpp"
#include "exoid/ident/estimators/stopwatch.hpp"

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace exoid::ident {

namespace {
const char* jointName(int j) { return j == 0 ? "hip" : "knee"; }

[[noreturn]] void bad(const std::string& field, const std::string& expected) {
  throw std::invalid_argument("'" + field + "' must be " + expected);
}
}  // namespace

void ExcitationLimits::validate() const {
  for (int j = 0; j < 2; ++j) {
    const std::string J = std::string("[") + jointName(j) + "]";
    if (!(q_min_rad[j] < q_max_rad[j])) bad("q_min_rad" + J + " < q_max_rad" + J, "true");
    if (!(qd_max_radps[j] > 0)) bad("qd_max_radps" + J, "> 0");
    if (!(qdd_max_radps2[j] > 0)) bad("qdd_max_radps2" + J, "> 0");
    if (!(tau_max_Nm[j] > 0)) bad("tau_max_Nm" + J, "> 0");
  }
}

namespace {
// Walks `samples` points of one period: the state and both regressor rows at each, and fills the
// design's regressor H (rows as excitationRegressor documents). One regressor evaluation per
// sample serves both the criterion and the limits.
template <typename Fn>
Eigen::MatrixXd sampleRegressor(const core::FourierSeries& traj, const LegConstants& c, int samples, Fn&& fn) {
  const double dt = traj.period_s() / samples;
  const bool knee_only = traj.locked_joints > 0;
  Eigen::MatrixXd H(knee_only ? samples : 2 * samples, knee_only ? kGroupSize : kNumParams);
  RegressorRow hip, knee;
  Eigen::Vector2d q, qd, qdd;
  for (int i = 0; i < samples; ++i) {
    traj.at(dt * i, q, qd, qdd);
    regressorRows(c, q, qd, qdd, hip, knee);
    if (knee_only) {
      H.row(i) = knee.segment<kGroupSize>(kShankFirst);
    } else {
      H.row(2 * i) = hip;
      H.row(2 * i + 1) = knee;
    }
    fn(q, qd, qdd, hip, knee);
  }
  return H;
}
}  // namespace

Eigen::MatrixXd excitationRegressor(const core::FourierSeries& traj, const LegConstants& c, int samples) {
  return sampleRegressor(traj, c, samples, [](const auto&...) {});
}

ExcitationScore scoreExcitation(const core::FourierSeries& traj, const LegConstants& c, const ParamVector& x_nominal,
                                const ExcitationLimits& limits, int samples) {
  traj.validate();
  if (traj.dof() != 2 || traj.locked_joints > 1) throw std::invalid_argument("excitation: the 2-link leg's trajectory moves hip and knee (the hip locked or not)");
  limits.validate();
  if (samples < 20) throw std::invalid_argument("excitation: need >= 20 samples per period");
  ExcitationScore s;
  s.q_min_rad.setConstant(std::numeric_limits<double>::infinity());
  s.q_max_rad.setConstant(-std::numeric_limits<double>::infinity());
  s.qd_max_radps.setZero();
  s.qdd_max_radps2.setZero();
  s.tau_max_Nm.setZero();
  const Eigen::MatrixXd H = sampleRegressor(
      traj, c, samples,
      [&](const Eigen::Vector2d& q, const Eigen::Vector2d& qd, const Eigen::Vector2d& qdd, const RegressorRow& hip,
          const RegressorRow& knee) {
        const Eigen::Vector2d tau(hip.dot(x_nominal), knee.dot(x_nominal));
        s.q_min_rad = s.q_min_rad.cwiseMin(q);
        s.q_max_rad = s.q_max_rad.cwiseMax(q);
        s.qd_max_radps = s.qd_max_radps.cwiseMax(qd.cwiseAbs());
        s.qdd_max_radps2 = s.qdd_max_radps2.cwiseMax(qdd.cwiseAbs());
        s.tau_max_Nm = s.tau_max_Nm.cwiseMax(tau.cwiseAbs());
      });
  const Eigen::VectorXd scale = columnScales(H);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(H * scale.asDiagonal(), Eigen::ComputeThinV);
  const Eigen::VectorXd sv = svd.singularValues();
  s.condition_number = sv[sv.size() - 1] > 0 ? sv[0] / sv[sv.size() - 1] : std::numeric_limits<double>::infinity();
  // (H^T H)^{-1} = S V diag(1 / sv^2) V^T S for H S = U diag(sv) V^T.
  for (Eigen::Index i = 0; i < H.cols(); ++i) {
    double var = 0.0;
    for (Eigen::Index k = 0; k < sv.size(); ++k) {
      var += sv[k] > 0 ? svd.matrixV()(i, k) * svd.matrixV()(i, k) / (sv[k] * sv[k]) : std::numeric_limits<double>::infinity();
    }
    const double std_i = scale[i] * std::sqrt(var);
    s.sum_log_std += std::log(std_i);
  }

  const auto check = [&](double excess, const std::string& name) {
    if (excess > s.worst_violation) {
      s.worst_violation = excess;
      s.worst_violation_name = name;
    }
  };
  for (int j = 0; j < 2; ++j) {
    const std::string J = std::string("[") + jointName(j) + "]";
    const double range = limits.q_max_rad[j] - limits.q_min_rad[j];
    check((limits.q_min_rad[j] - s.q_min_rad[j]) / range, "q_min" + J);
    check((s.q_max_rad[j] - limits.q_max_rad[j]) / range, "q_max" + J);
    if (j == 0 && traj.locked_joints > 0) continue;  // the lock holds the hip: no motion, no motor torque
    check(s.qd_max_radps[j] / limits.qd_max_radps[j] - 1.0, "qd" + J);
    check(s.qdd_max_radps2[j] / limits.qdd_max_radps2[j] - 1.0, "qdd" + J);
    check(s.tau_max_Nm[j] / limits.tau_max_Nm[j] - 1.0, "tau" + J);
  }
  return s;
}

const char* toString(ExcitationCriterion c) { return c == ExcitationCriterion::kCrb ? "crb" : "cond"; }

ExcitationCriterion parseExcitationCriterion(const std::string& name) {
  if (name == "crb") return ExcitationCriterion::kCrb;
  if (name == "cond") return ExcitationCriterion::kConditionNumber;
  throw std::invalid_argument("unknown excitation criterion '" + name + "'; expected crb or cond");
}

namespace {
// max |sin| and |cos| over [lo, hi].
double maxAbsSin(double lo, double hi) {
  if (hi - lo >= M_PI) return 1.0;
  const double k = std::ceil((lo - M_PI / 2) / M_PI);  // first pi/2 + k pi >= lo
  if (M_PI / 2 + k * M_PI <= hi) return 1.0;
  return std::max(std::abs(std::sin(lo)), std::abs(std::sin(hi)));
}
double maxAbsCos(double lo, double hi) { return maxAbsSin(lo + M_PI / 2, hi + M_PI / 2); }
}  // namespace

Eigen::VectorXd crbFloor(const ExcitationLimits& lim, const LegConstants& c, bool hip_locked, double hip_locked_at_rad,
                         double rows, double sigma) {
  lim.validate();
  c.validate();
  if (!(rows > 0) || !(sigma > 0)) throw std::invalid_argument("crbFloor: rows and sigma must be > 0");
  const double L = c.thigh_length_m, g = c.gravity_mps2;
  const double q1lo = hip_locked ? hip_locked_at_rad : lim.q_min_rad[0], q1hi = hip_locked ? hip_locked_at_rad : lim.q_max_rad[0];
  const double V1 = hip_locked ? 0.0 : lim.qd_max_radps[0], A1 = hip_locked ? 0.0 : lim.qdd_max_radps2[0];
  const double V2 = lim.qd_max_radps[1], A2 = lim.qdd_max_radps2[1];
  const double S1 = maxAbsSin(q1lo, q1hi), C1 = maxAbsCos(q1lo, q1hi);
  const double S2 = maxAbsSin(lim.q_min_rad[1], lim.q_max_rad[1]), C2 = maxAbsCos(lim.q_min_rad[1], lim.q_max_rad[1]);
  const double S12 = maxAbsSin(q1lo + lim.q_min_rad[1], q1hi + lim.q_max_rad[1]);
  const double C12 = maxAbsCos(q1lo + lim.q_min_rad[1], q1hi + lim.q_max_rad[1]);
  const double a = V2 * (2 * V1 + V2);  // |qd1^2 - (qd1 + qd2)^2|
  // Bounds on |column| in the hip and the knee row (paper.md's regressor, term by term).
  ParamVector hip, knee;
  hip << g * S1, g * C1, A1, 1.0, V1, L * ((2 * A1 + A2) * C2 + a * S2) + g * S12, L * ((2 * A1 + A2) * S2 + a * C2) + g * C12, A2,
      0.0, 0.0;
  knee << 0.0, 0.0, 0.0, 0.0, 0.0, L * (A1 * C2 + V1 * V1 * S2) + g * S12, L * (A1 * S2 + V1 * V1 * C2) + g * C12, A1 + A2, 1.0,
      V2;
  if (hip_locked) hip.setZero();  // a knee-only design uses the knee equation alone
  const int first = hip_locked ? kShankFirst : 0;
  Eigen::VectorXd floor(kNumParams - first);
  for (int i = first; i < kNumParams; ++i) {
    floor[i - first] = sigma / std::sqrt(rows * (hip[i] * hip[i] + knee[i] * knee[i]));
  }
  return floor;
}

void ExcitationOptions::validate() const {
  if (harmonics < 2) bad("harmonics", ">= 2 (the first harmonic is set by the rest-at-the-ends rule)");
  if (!(f0_hz > 0 && std::isfinite(f0_hz))) bad("f0_hz", "> 0");
  if (restarts < 1) bad("restarts", ">= 1");
  if (max_evaluations < 100) bad("max_evaluations", ">= 100");
  if (samples < 20) bad("samples", ">= 20");
  if (!std::isfinite(hip_locked_at_rad)) bad("hip_locked_at_rad", "finite");
}

int unpackRestingHarmonics(const Eigen::VectorXd& p, int at, Eigen::Ref<Eigen::VectorXd> a, Eigen::Ref<Eigen::VectorXd> b) {
  const Eigen::Index n = a.size();
  double sa = 0.0, sb = 0.0;
  for (Eigen::Index k = 2; k <= n; ++k) {
    a[k - 1] = p[at++];
    sa += double(k * k) * a[k - 1];
  }
  for (Eigen::Index k = 2; k <= n; ++k) {
    b[k - 1] = p[at++];
    sb += double(k) * b[k - 1];
  }
  a[0] = -sa;
  b[0] = -sb;
  return at;
}

namespace {

// The free coefficients of one joint: offset, a_2..a_N, b_2..b_N (2N - 1 numbers); a_1 and b_1
// follow from zero velocity and acceleration at t = 0.
constexpr int kFreePerJoint(int n) { return 2 * n - 1; }

core::FourierSeries fromFree(const ExcitationOptions& o, const Eigen::VectorXd& p) {
  const int n = o.harmonics;
  core::FourierSeries t = core::FourierSeries::still(2, n, o.f0_hz);
  t.locked_joints = o.hip_locked ? 1 : 0;
  t.offset_rad << o.hip_locked_at_rad, 0.0;
  int at = 0;
  for (int j = o.hip_locked ? 1 : 0; j < 2; ++j) {
    t.offset_rad[j] = p[at++];
    at = unpackRestingHarmonics(p, at, t.a_rad.col(j), t.b_rad.col(j));
  }
  return t;
}

// The same trajectory with every harmonic scaled by s (offsets kept).
core::FourierSeries shrunk(core::FourierSeries t, double s) {
  t.a_rad *= s;
  t.b_rad *= s;
  return t;
}

}  // namespace

RestartSearch searchFromRestarts(const ExcitationOptions& o, const std::function<Eigen::VectorXd(core::Rng&)>& start,
                                 const std::function<double(const Eigen::VectorXd&)>& objective,
                                 const std::function<bool(const Eigen::VectorXd&)>& feasible) {
  core::Rng rng(o.seed);
  double best_feasible = std::numeric_limits<double>::infinity(), best_any = best_feasible;
  Eigen::VectorXd p_feasible, p_any;
  NelderMeadOptions nm;
  nm.max_evaluations = o.max_evaluations;
  nm.initial_step = 0.05;
  nm.f_tolerance = 1e-8;
  nm.x_tolerance = 1e-6;
  RestartSearch out;
  for (int r = 0; r < o.restarts; ++r) {
    const NelderMeadResult res = minimizeNelderMead(objective, start(rng), nm);
    out.evaluations += res.evaluations;
    if (feasible(res.x)) {
      ++out.feasible_restarts;
      if (res.f < best_feasible) {
        best_feasible = res.f;
        p_feasible = res.x;
      }
    }
    if (res.f < best_any) {
      best_any = res.f;
      p_any = res.x;
    }
  }
  out.x = p_feasible.size() ? p_feasible : p_any;
  return out;
}

double largestFeasibleScale(const std::function<bool(double)>& feasible_at) {
  double lo = 0.0, hi = 1.0;
  for (int it = 0; it < 40; ++it) {
    const double mid = 0.5 * (lo + hi);
    (feasible_at(mid) ? lo : hi) = mid;
  }
  return lo;
}

ExcitationDesign designExcitation(const ExcitationOptions& o, const LegConstants& c, const ParamVector& x_nominal,
                                  const ExcitationLimits& limits) {
  o.validate();
  limits.validate();
  c.validate();
  const Stopwatch watch;
  const int joints = o.hip_locked ? 1 : 2;
  const int dim = joints * kFreePerJoint(o.harmonics);
  ExcitationDesign d;
  const auto objective = [&](const Eigen::VectorXd& p) {
    const ExcitationScore s = scoreExcitation(fromFree(o, p), c, x_nominal, limits, o.samples);
    // Both criteria are logarithms, so the penalty dominates any violation beyond a few percent.
    const double f = o.criterion == ExcitationCriterion::kCrb ? s.sum_log_std : std::log(s.condition_number);
    return f + 1e5 * s.worst_violation * s.worst_violation;
  };
  const RestartSearch found = searchFromRestarts(
      o,
      [&](core::Rng& rng) {
        // A random start inside the middle of the range with small, decaying harmonics.
        Eigen::VectorXd p(dim);
        int at = 0;
        for (int j = o.hip_locked ? 1 : 0; j < 2; ++j) {
          const double mid = 0.5 * (limits.q_min_rad[j] + limits.q_max_rad[j]);
          const double half = 0.5 * (limits.q_max_rad[j] - limits.q_min_rad[j]);
          p[at++] = mid + 0.25 * half * rng.uniform(-1.0, 1.0);
          for (int k = 0; k < 2 * (o.harmonics - 1); ++k) p[at++] = 0.15 * half * rng.uniform(-1.0, 1.0) / (1 + k % (o.harmonics - 1));
        }
        return p;
      },
      objective,
      [&](const Eigen::VectorXd& p) { return scoreExcitation(fromFree(o, p), c, x_nominal, limits, o.samples).worst_violation == 0.0; });
  d.evaluations = found.evaluations;
  d.feasible_restarts = found.feasible_restarts;
  core::FourierSeries t = fromFree(o, found.x);
  // Limits are checked on 1000 samples at the end: peaks between the optimiser's samples, or no
  // feasible end point at all, are repaired by shrinking the harmonics (bisection on the scale).
  if (scoreExcitation(t, c, x_nominal, limits, 1000).worst_violation > 0.0) {
    t = shrunk(t, largestFeasibleScale([&](double s) { return !(scoreExcitation(shrunk(t, s), c, x_nominal, limits, 1000).worst_violation > 0.0); }));
  }
  d.trajectory = t;
  d.score = scoreExcitation(t, c, x_nominal, limits, 1000);
  d.wall_time_s = watch.seconds();
  return d;
}

}  // namespace exoid::ident
