#pragma once
// Excitation design (Swevers, Ganseman, Tukel, de Schutter, Van Brussel 1997): periodic finite
// Fourier series trajectories, rated by how well the regressor they produce determines the
// parameters, under the rig's limits. Pure Eigen, so a user can design for their own rig from its nominal parameters.
//
// Per joint: q(t) = offset + sum_{k=1..N} a_k cos(k w t) + b_k sin(k w t), w = 2 pi f0. Zero
// velocity and acceleration at t = 0 (and so at every period's end) are built in: the first
// harmonic's coefficients follow from the others (b_1 = -sum_{k>=2} k b_k, a_1 = -sum_{k>=2} k^2 a_k),
// so every trajectory the optimiser sees starts and ends at rest.
#include "exoid/core/fourier_series.hpp"
#include "exoid/core/random.hpp"
#include "exoid/ident/leg/params.hpp"
#include "exoid/ident/leg/regressor.hpp"

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>

namespace exoid::ident {

/// The rig's limits the design must respect (SI). Torques from the nominal model's inverse dynamics.
struct ExcitationLimits {
  Eigen::Vector2d q_min_rad{-1.4, 0.05}, q_max_rad{0.5, 1.9};
  Eigen::Vector2d qd_max_radps{3.0, 3.0};
  Eigen::Vector2d qdd_max_radps2{30.0, 30.0};
  Eigen::Vector2d tau_max_Nm{120.0, 60.0};
  void validate() const;  ///< throws std::invalid_argument naming the field
};

/// What a design minimises.
enum class ExcitationCriterion {
  /// sum_i log std_i: the noise-limited standard deviations of the LS estimates of the design's
  /// parameters (unit white noise per row). It equals -1/2 log det(information) (D-optimality,
  /// Swevers et al. 1997) plus -1/2 log det(correlation matrix of the estimates) >= 0, which is 0
  /// only when the estimates are uncorrelated: every parameter counts equally in relative terms,
  /// it needs no nominal values, and a parameter's units only add a constant. Rewards amplitude.
  kCrb,
  /// log of the condition number of the column-scaled regressor (Gautier & Khalil 1992). Scale
  /// free: met as well by small, slow motions that determine every parameter poorly.
  kConditionNumber,
};
const char* toString(ExcitationCriterion c);
/// "crb" or "cond"; throws std::invalid_argument listing both.
ExcitationCriterion parseExcitationCriterion(const std::string& name);

/// How good a trajectory is, evaluated on `samples` points of one period.
struct ExcitationScore {
  /// Condition number of the column-scaled regressor the design is for (both equations, all 10
  /// columns; knee-only designs: the knee equation's 5 shank columns).
  double condition_number = 0.0;
  /// sum_i log std_i of the design's parameters (the kCrb criterion; same footing).
  double sum_log_std = 0.0;
  /// Largest excess over the limits, relative to each limit (0 = feasible).
  double worst_violation = 0.0;
  std::string worst_violation_name;    ///< e.g. "qd[knee]"; empty when feasible
  Eigen::Vector2d q_min_rad, q_max_rad, qd_max_radps, qdd_max_radps2, tau_max_Nm;  ///< reached
};

/// Scores a trajectory for the nominal parameters x_nominal (torques) and constants c.
ExcitationScore scoreExcitation(const core::FourierSeries& traj, const LegConstants& c, const ParamVector& x_nominal,
                                const ExcitationLimits& limits, int samples = 1000);

/// The regressor the design is for, on `samples` points of one period (rows: both equations in
/// time order, or the knee equation's shank columns for a locked hip).
Eigen::MatrixXd excitationRegressor(const core::FourierSeries& traj, const LegConstants& c, int samples);

/// A floor no trajectory inside `limits` can beat: for each of the design's parameters, the
/// std of its LS estimate from `rows` samples per equation with white noise sigma is at least
/// sigma / sqrt(rows * (b_hip^2 + b_knee^2)), where b is a bound on |its regressor column| over
/// every state inside the limits (Cauchy-Schwarz: correlations with other columns only raise the
/// std). Coulomb friction's column is sgn(qd): its floor is sigma / sqrt(rows) whatever the limits.
/// Bounds use the joint ranges, |qd| and |qdd| limits (not the torque limit).
Eigen::VectorXd crbFloor(const ExcitationLimits& limits, const LegConstants& c, bool hip_locked, double hip_locked_at_rad,
                         double rows, double sigma);

struct ExcitationOptions {
  ExcitationCriterion criterion = ExcitationCriterion::kCrb;
  int harmonics = 5;          ///< N, >= 2 (the first harmonic is fixed by the rest-at-the-ends rule)
  /// Base frequency, > 0: a 5 s period whose 5th harmonic is the paper's 1 Hz, so the design asks
  /// no faster motion of the rig than the paper's trajectories did.
  double f0_hz = 0.2;
  bool hip_locked = false;    ///< design the knee-only record (the segmental strategy's first stage)
  double hip_locked_at_rad = -10.0 * M_PI / 180.0;  ///< where the locked hip is held (the paper's -10 deg)
  int restarts = 8;           ///< random starting points, >= 1
  long max_evaluations = 6000;  ///< per restart, >= 100
  int samples = 200;          ///< points per period while optimising (the result is rescored on 1000)
  std::uint64_t seed = 1;     ///< all randomness; same seed, same design
  void validate() const;      ///< throws std::invalid_argument naming the field
};

struct ExcitationDesign {
  core::FourierSeries trajectory;
  ExcitationScore score;      ///< on 1000 samples
  long evaluations = 0;
  int feasible_restarts = 0;  ///< restarts that ended inside the limits
  double wall_time_s = 0.0;
};

/// The search both excitation designs run (this leg's and any chain's, design/robot_excitation.hpp):
/// Nelder-Mead on `objective` from options.restarts starts drawn by `start` from one generator
/// seeded with options.seed; the best end point `feasible` accepts, else the best of all.
struct RestartSearch {
  Eigen::VectorXd x;
  long evaluations = 0;
  int feasible_restarts = 0;
};
RestartSearch searchFromRestarts(const ExcitationOptions& options, const std::function<Eigen::VectorXd(core::Rng&)>& start,
                                 const std::function<double(const Eigen::VectorXd&)>& objective,
                                 const std::function<bool(const Eigen::VectorXd&)>& feasible);
/// One joint's harmonics from a design's free coefficients p[at..]: a_2..a_N then b_2..b_N into
/// a(1..N-1), b(1..N-1); a_1 and b_1 follow from rest at t = 0 (sum k^2 a_k = 0: qdd(0) = 0;
/// sum k b_k = 0: qd(0) = 0). a and b hold N each. Returns the index after the last one read.
int unpackRestingHarmonics(const Eigen::VectorXd& p, int at, Eigen::Ref<Eigen::VectorXd> a, Eigen::Ref<Eigen::VectorXd> b);
/// The largest s in [0, 1] (40 bisection steps) with feasible_at(s), for shrinking a design's
/// harmonics into the limits; feasible_at(0) is assumed.
double largestFeasibleScale(const std::function<bool(double)>& feasible_at);

/// Minimises the criterion + a penalty on the limits' violations by Nelder-Mead from `restarts`
/// random starts (all from options.seed), keeps the best feasible end point, and if none is
/// feasible shrinks the harmonics of the best until it is. Deterministic.
ExcitationDesign designExcitation(const ExcitationOptions& options, const LegConstants& c, const ParamVector& x_nominal,
                                  const ExcitationLimits& limits);

}  // namespace exoid::ident
