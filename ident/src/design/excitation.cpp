#include "exoid/ident/design/excitation.hpp"

#include "exoid/core/format.hpp"
#include "exoid/core/random.hpp"
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/estimators/nelder_mead.hpp"
#include "exoid/ident/estimators/stopwatch.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>

namespace exoid::ident {

namespace {
constexpr double kTwoPi = 6.283185307179586;
constexpr double kInf = std::numeric_limits<double>::infinity();

[[noreturn]] void bad(const std::string& field, const std::string& expected) {
  throw std::invalid_argument("'" + field + "' must be " + expected);
}
}  // namespace

void ExcitationLimits::validate(const std::vector<std::string>& joints) const {
  const auto dof = static_cast<Eigen::Index>(joints.size());
  for (const Eigen::VectorXd* v : {&q_min_rad, &q_max_rad, &qd_max_radps, &qdd_max_radps2, &tau_max_Nm}) {
    if (v->size() != dof) throw std::invalid_argument("excitation limits: one entry per joint (" + core::toText(dof) + ") expected");
  }
  for (Eigen::Index j = 0; j < dof; ++j) {
    const std::string J = "[" + joints[static_cast<std::size_t>(j)] + "]";
    if (!(q_min_rad[j] < q_max_rad[j])) bad("q_min_rad" + J + " < q_max_rad" + J, "true");
    if (!(qd_max_radps[j] > 0)) bad("qd_max_radps" + J, "> 0");
    if (!(qdd_max_radps2[j] > 0)) bad("qdd_max_radps2" + J, "> 0");
    if (!(tau_max_Nm[j] > 0)) bad("tau_max_Nm" + J, "> 0");
  }
}

ExcitationLimits ExcitationLimits::twoLinkLeg() {
  ExcitationLimits l;
  l.q_min_rad = Eigen::Vector2d(-1.4, 0.05);
  l.q_max_rad = Eigen::Vector2d(0.5, 1.9);
  l.qd_max_radps = Eigen::Vector2d(3.0, 3.0);
  l.qdd_max_radps2 = Eigen::Vector2d(30.0, 30.0);
  l.tau_max_Nm = Eigen::Vector2d(120.0, 60.0);
  return l;
}

const char* toString(ExcitationCriterion c) { return c == ExcitationCriterion::kCrb ? "crb" : "cond"; }

ExcitationCriterion parseExcitationCriterion(const std::string& name) {
  if (name == "crb") return ExcitationCriterion::kCrb;
  if (name == "cond") return ExcitationCriterion::kConditionNumber;
  throw std::invalid_argument("unknown excitation criterion '" + name + "'; expected crb or cond");
}

std::vector<int> excitationParameters(const Robot& robot, int locked_joints, const Eigen::VectorXd& locked_at_rad) {
  const int dof = robot.dof(), locked = std::max(locked_joints, 0);
  std::vector<int> touched;
  for (int j = locked; j < dof; ++j) {
    for (int c : robot.joint_columns[static_cast<std::size_t>(j)]) {
      if (std::find(touched.begin(), touched.end(), c) == touched.end()) touched.push_back(c);
    }
  }
  std::sort(touched.begin(), touched.end());
  if (locked == 0) return touched;
  // With joints held still, a column the moving equations touch can be a combination of the
  // others (a held hip leaves the knee's armature column equal to its link inertia's): kept in
  // column order when it adds a direction, judged as base parameters are (base_parameters.hpp).
  const BaseParameterOptions structure;
  const Eigen::MatrixXd rows = heldJointRows(robot, locked, structure, locked_at_rad);
  std::vector<int> kept;
  Eigen::MatrixXd basis(rows.rows(), 0);
  for (int c : touched) {
    const double norm = rows.col(c).norm();
    if (!(norm > 0.0)) continue;
    Eigen::VectorXd v = rows.col(c) / norm;
    for (int pass = 0; pass < 2; ++pass) v -= basis * (basis.transpose() * v);  // Gram-Schmidt, twice
    // A unit column's residual is its pivot in a QR of the unit columns: the base parameters' rule.
    if (v.norm() <= structure.tolerance) continue;
    basis.conservativeResize(Eigen::NoChange, basis.cols() + 1);
    basis.col(basis.cols() - 1) = v.normalized();
    kept.push_back(c);
  }
  return kept;
}

namespace {

// One period's sample times and each harmonic's cosine and sine there, computed once for the
// thousands of trajectories a design rates (the trigonometry was a tenth of its time).
struct PeriodGrid {
  Eigen::VectorXd w;     ///< per harmonic, rad/s
  Eigen::MatrixXd c, s;  ///< samples x harmonics
  PeriodGrid(double f0, int harmonics, int samples) : w(harmonics), c(samples, harmonics), s(samples, harmonics) {
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
// (the condition number too: an SVD the CRB criterion does not use).
enum class Rating { kLimits, kCrb, kFull };

void checkSizes(const Robot& robot, const core::FourierSeries& t, const Eigen::VectorXd& theta_nominal, const ExcitationLimits& limits) {
  t.validate();
  if (t.dof() != robot.dof()) {
    throw std::invalid_argument("excitation: the trajectory moves " + core::toText(t.dof()) + " joints, the robot has " + core::toText(robot.dof()));
  }
  if (t.locked_joints >= robot.dof()) throw std::invalid_argument("excitation: every joint is locked");
  if (theta_nominal.size() != robot.parameters()) throw std::invalid_argument("excitation: theta_nominal has the wrong size");
  limits.validate(robot.jointNames());
}

// The moving joints' rows over the design's parameters (into rows_out when given), the reached
// extremes and the limits' worst violation; the criterion's numbers when `rating` asks for them.
ExcitationScore scoreOnGrid(const Robot& robot, const core::FourierSeries& t, const Eigen::VectorXd& theta_nominal, const ExcitationLimits& limits,
                            const PeriodGrid& grid, const std::vector<int>& columns, Rating rating, Eigen::MatrixXd* rows_out = nullptr) {
  const int dof = robot.dof(), locked = t.locked_joints, moving = dof - locked;
  const int samples = grid.samples();
  Eigen::MatrixXd H(static_cast<Eigen::Index>(samples) * moving, static_cast<Eigen::Index>(columns.size()));
  Eigen::MatrixXd rows(dof, robot.parameters());
  RobotWorkspace work;
  Eigen::VectorXd q, qd, qdd;
  ExcitationScore s;
  s.q_min_rad = Eigen::VectorXd::Constant(dof, kInf);
  s.q_max_rad = Eigen::VectorXd::Constant(dof, -kInf);
  s.qd_max_radps = s.qdd_max_radps2 = s.tau_max_Nm = Eigen::VectorXd::Zero(dof);
  const ChainBaseMotion still = ChainBaseMotion::still(robot.chain);
  for (int i = 0; i < samples; ++i) {
    grid.at(t, i, q, qd, qdd);
    robotRowsInto(robot, q, qd, qdd, still, work, rows);
    const Eigen::VectorXd tau = rows * theta_nominal;
    s.q_min_rad = s.q_min_rad.cwiseMin(q);
    s.q_max_rad = s.q_max_rad.cwiseMax(q);
    s.qd_max_radps = s.qd_max_radps.cwiseMax(qd.cwiseAbs());
    s.qdd_max_radps2 = s.qdd_max_radps2.cwiseMax(qdd.cwiseAbs());
    s.tau_max_Nm = s.tau_max_Nm.cwiseMax(tau.cwiseAbs());
    for (int j = locked; j < dof; ++j) {
      for (std::size_t c = 0; c < columns.size(); ++c) {
        H(static_cast<Eigen::Index>(i) * moving + (j - locked), static_cast<Eigen::Index>(c)) = rows(j, columns[c]);
      }
    }
  }
  const auto check = [&](double excess, const char* what, int j) {
    if (excess > s.worst_violation) {
      s.worst_violation = excess;
      s.worst_violation_name = std::string(what) + "[" + robot.chain.joints[static_cast<std::size_t>(j)].name + "]";
    }
  };
  for (int j = 0; j < dof; ++j) {
    const double range = limits.q_max_rad[j] - limits.q_min_rad[j];
    const double span = std::isfinite(range) ? range : 1.0;
    check((limits.q_min_rad[j] - s.q_min_rad[j]) / span, "q_min", j);
    check((s.q_max_rad[j] - limits.q_max_rad[j]) / span, "q_max", j);
    if (j < locked) continue;  // the lock holds it: no motion, no motor torque
    check(s.qd_max_radps[j] / limits.qd_max_radps[j] - 1.0, "qd", j);
    check(s.qdd_max_radps2[j] / limits.qdd_max_radps2[j] - 1.0, "qdd", j);
    check(s.tau_max_Nm[j] / limits.tau_max_Nm[j] - 1.0, "tau", j);
  }
  if (rows_out) *rows_out = H;
  if (rating == Rating::kLimits) return s;
  const Eigen::VectorXd norms = H.colwise().norm().transpose();
  if (rating == Rating::kFull) s.condition_number = scaledConditionNumber(H);
  // Cramer-Rao stds with unit noise per row: sqrt of diag((H' H)^-1), through the scaled
  // columns' Cholesky (their Gram matrix is well scaled); a singular one scores +infinity.
  for (Eigen::Index c = 0; c < H.cols(); ++c) H.col(c) /= std::max(norms[c], 1e-300);
  const Eigen::LLT<Eigen::MatrixXd> llt(H.transpose() * H);
  if (llt.info() != Eigen::Success || (rating == Rating::kFull && !std::isfinite(s.condition_number))) {
    s.sum_log_std = kInf;
    return s;
  }
  const Eigen::MatrixXd inv = llt.solve(Eigen::MatrixXd::Identity(H.cols(), H.cols()));
  for (Eigen::Index c = 0; c < H.cols(); ++c) s.sum_log_std += 0.5 * std::log(inv(c, c)) - std::log(std::max(norms[c], 1e-300));
  if (!std::isfinite(s.sum_log_std)) s.sum_log_std = kInf;  // numerically singular
  return s;
}

// The parameters a trajectory's rows determine, its held joints where it holds them.
std::vector<int> designColumns(const Robot& robot, const core::FourierSeries& t) {
  return excitationParameters(robot, t.locked_joints, t.offset_rad.head(t.locked_joints));
}

}  // namespace

ExcitationScore scoreExcitation(const Robot& robot, const core::FourierSeries& t, const Eigen::VectorXd& theta_nominal,
                                const ExcitationLimits& limits, int samples) {
  checkSizes(robot, t, theta_nominal, limits);
  if (samples < 20) throw std::invalid_argument("excitation: need >= 20 samples per period");
  return scoreOnGrid(robot, t, theta_nominal, limits, PeriodGrid(t.f0_hz, t.harmonics(), samples), designColumns(robot, t), Rating::kFull);
}

Eigen::MatrixXd excitationRegressor(const Robot& robot, const core::FourierSeries& t, int samples) {
  if (samples < 1) throw std::invalid_argument("excitation: need >= 1 sample per period");
  ExcitationLimits wide;
  wide.q_min_rad = Eigen::VectorXd::Constant(robot.dof(), -kInf);
  wide.q_max_rad = wide.qd_max_radps = wide.qdd_max_radps2 = wide.tau_max_Nm = Eigen::VectorXd::Constant(robot.dof(), kInf);
  checkSizes(robot, t, Eigen::VectorXd::Zero(robot.parameters()), wide);
  Eigen::MatrixXd H;
  scoreOnGrid(robot, t, Eigen::VectorXd::Zero(robot.parameters()), wide, PeriodGrid(t.f0_hz, t.harmonics(), samples), designColumns(robot, t),
              Rating::kLimits, &H);
  return H;
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
  lim.validate({"hip", "knee"});
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
  if (locked_joints < 0 || locked_at_rad.size() != locked_joints) bad("locked_at_rad", "one angle per locked joint");
  if (!locked_at_rad.allFinite()) bad("locked_at_rad", "finite");
}

namespace {

// One joint's harmonics from the free coefficients p[at..]: a_2..a_N then b_2..b_N; a_1 and b_1
// follow from rest at t = 0 (sum k^2 a_k = 0: qdd(0) = 0; sum k b_k = 0: qd(0) = 0).
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

// Free coefficients per moving joint: offset, a_2..a_N, b_2..b_N; a locked joint sits at its lock.
core::FourierSeries fromFree(const ExcitationOptions& o, int dof, const Eigen::VectorXd& p) {
  core::FourierSeries t = core::FourierSeries::still(dof, o.harmonics, o.f0_hz);
  t.locked_joints = o.locked_joints;
  int at = 0;
  for (int j = 0; j < dof; ++j) {
    if (j < o.locked_joints) {
      t.offset_rad[j] = o.locked_at_rad[j];
      continue;
    }
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

// Nelder-Mead on `objective` from o.restarts starts drawn by `start` from one generator seeded
// with o.seed; the best end point `feasible` accepts, else the best of all.
struct RestartSearch {
  Eigen::VectorXd x;
  long evaluations = 0;
  int feasible_restarts = 0;
};
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

// The largest s in [0, 1] (40 bisection steps) with feasible_at(s); feasible_at(0) is assumed.
double largestFeasibleScale(const std::function<bool(double)>& feasible_at) {
  double lo = 0.0, hi = 1.0;
  for (int it = 0; it < 40; ++it) {
    const double mid = 0.5 * (lo + hi);
    (feasible_at(mid) ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

ExcitationDesign designExcitation(const ExcitationOptions& o, const Robot& robot, const Eigen::VectorXd& theta_nominal,
                                  const ExcitationLimits& limits) {
  o.validate();
  const int dof = robot.dof();
  if (o.locked_joints >= dof) throw std::invalid_argument("excitation: every joint is locked (locked_joints " + core::toText(o.locked_joints) + ")");
  checkSizes(robot, core::FourierSeries::still(dof, o.harmonics, o.f0_hz), theta_nominal, limits);
  const Stopwatch watch;
  const int dim = (dof - o.locked_joints) * (2 * o.harmonics - 1);
  const PeriodGrid coarse(o.f0_hz, o.harmonics, o.samples), fine(o.f0_hz, o.harmonics, 1000);
  const std::vector<int> columns = excitationParameters(robot, o.locked_joints, o.locked_at_rad);
  const auto score = [&](const core::FourierSeries& t, const PeriodGrid& grid, Rating rating) {
    return scoreOnGrid(robot, t, theta_nominal, limits, grid, columns, rating);
  };
  const Rating criterion = o.criterion == ExcitationCriterion::kCrb ? Rating::kCrb : Rating::kFull;
  const auto objective = [&](const Eigen::VectorXd& p) {
    const ExcitationScore s = score(fromFree(o, dof, p), coarse, criterion);
    // Both criteria are logarithms, so the penalty dominates any violation beyond a few percent.
    const double f = o.criterion == ExcitationCriterion::kCrb ? s.sum_log_std : std::log(s.condition_number);
    return f + 1e5 * s.worst_violation * s.worst_violation;
  };
  const RestartSearch found = searchFromRestarts(
      o,
      [&](core::Rng& rng) {
        // About the middle of each moving joint's range (0 without one), small decaying harmonics.
        Eigen::VectorXd p(dim);
        int at = 0;
        for (int j = o.locked_joints; j < dof; ++j) {
          const bool ranged = std::isfinite(limits.q_min_rad[j]) && std::isfinite(limits.q_max_rad[j]);
          const double mid = ranged ? 0.5 * (limits.q_min_rad[j] + limits.q_max_rad[j]) : 0.0;
          const double half = ranged ? 0.5 * (limits.q_max_rad[j] - limits.q_min_rad[j]) : 1.0;
          p[at++] = mid + 0.25 * half * rng.uniform(-1.0, 1.0);
          for (int k = 0; k < 2 * (o.harmonics - 1); ++k) p[at++] = 0.15 * half * rng.uniform(-1.0, 1.0) / (1 + k % (o.harmonics - 1));
        }
        return p;
      },
      objective, [&](const Eigen::VectorXd& p) { return score(fromFree(o, dof, p), coarse, Rating::kLimits).worst_violation == 0.0; });
  ExcitationDesign d;
  d.evaluations = found.evaluations;
  d.feasible_restarts = found.feasible_restarts;
  core::FourierSeries t = fromFree(o, dof, found.x);
  // Limits are checked on 1000 samples at the end: peaks between the optimiser's samples, or no
  // feasible end point at all, are repaired by shrinking the harmonics (bisection on the scale).
  if (score(t, fine, Rating::kLimits).worst_violation > 0.0) {
    t = shrunk(t, largestFeasibleScale([&](double s) { return !(score(shrunk(t, s), fine, Rating::kLimits).worst_violation > 0.0); }));
  }
  d.trajectory = t;
  d.score = score(t, fine, Rating::kFull);
  d.wall_time_s = watch.seconds();
  return d;
}

}  // namespace exoid::ident
