#pragma once
// Excitation design (Swevers, Ganseman, Tukel, de Schutter, Van Brussel 1997) for any robot: a
// periodic finite Fourier series per joint, rated by how well the rows it produces determine the
// robot's parameters (the 2-link leg's X, a chain's base parameters), under the joints' limits.
// Pure Eigen, so a user can design for their own rig from its nominal parameters.
//
// Per joint: q(t) = offset + sum_{k=1..N} a_k cos(k w t) + b_k sin(k w t), w = 2 pi f0. Zero
// velocity and acceleration at t = 0 (and so at every period's end) are built in: the first
// harmonic's coefficients follow from the others (b_1 = -sum_{k>=2} k b_k, a_1 = -sum_{k>=2} k^2 a_k),
// so every trajectory the optimiser sees starts and ends at rest. The first locked_joints joints
// may be held by a lock (a segmental strategy's stage: the APAL leg's knee-only record): their
// equations are the lock's, and the design rates the moving joints' equations over the parameters
// those equations touch.
#include "exoid/core/fourier_series.hpp"
#include "exoid/ident/leg/params.hpp"
#include "exoid/ident/leg/regressor.hpp"
#include "exoid/ident/model/robot.hpp"

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <string>

namespace exoid::ident {

/// The joints' limits a design must respect (SI), one entry per joint; +infinity (-infinity for
/// q_min) where the robot gives none. Torques from the nominal model's inverse dynamics.
struct ExcitationLimits {
  Eigen::VectorXd q_min_rad, q_max_rad, qd_max_radps, qdd_max_radps2, tau_max_Nm;
  /// Sizes (dof), order, positive rates; throws std::invalid_argument naming the field and joint.
  void validate(const std::vector<std::string>& joints) const;
  /// A generic envelope of the APAL leg (hip, knee) for tests and examples; `exoid excite` uses
  /// the paper's trajectories' envelope or the URDF's limits.
  static ExcitationLimits twoLinkLeg();
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
  double condition_number = 0.0;  ///< of the column-scaled rows the design is for
  double sum_log_std = 0.0;       ///< sum of log Cramer-Rao stds of the design's parameters (kCrb)
  double worst_violation = 0.0;   ///< largest excess over a limit, relative to the limit (0 = feasible)
  std::string worst_violation_name;  ///< e.g. "qd[knee]"; empty when feasible
  Eigen::VectorXd q_min_rad, q_max_rad, qd_max_radps, qdd_max_radps2, tau_max_Nm;  ///< reached, per joint
};

/// The parameters a trajectory's rows determine: those the moving joints' equations touch
/// (robot.joint_columns), all of them when no joint is locked. With the first locked_joints held
/// (at locked_at_rad, one each; at any angle when empty), a touched column that is a combination of
/// earlier ones in the moving equations (robot.hpp's heldJointRows, judged by the base parameters'
/// tolerance) is left out (a held hip: a knee armature's column is its link inertia's), so the
/// design is for what such a record can identify. Throws std::invalid_argument on a wrong count.
std::vector<int> excitationParameters(const Robot& robot, int locked_joints, const Eigen::VectorXd& locked_at_rad = {});

/// Scores a trajectory for nominal parameters theta_nominal (the robot's; torques). A locked
/// joint's range is checked (where its lock holds it), not its rates or torque.
ExcitationScore scoreExcitation(const Robot& robot, const core::FourierSeries& t, const Eigen::VectorXd& theta_nominal,
                                const ExcitationLimits& limits, int samples = 1000);

/// The rows the design is for, on `samples` points of one period: the moving joints' equations in
/// time order, over excitationParameters' columns.
Eigen::MatrixXd excitationRegressor(const Robot& robot, const core::FourierSeries& t, int samples);

/// The 2-link leg (limits for hip, knee): a floor no trajectory inside `limits` can beat. For each
/// of the design's parameters (all 10, or the knee's 5 when the hip is locked), the std of its LS
/// estimate from `rows` samples per equation with white noise sigma is at least
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
  /// The first locked_joints joints are held by a lock at locked_at_rad (one entry each): the
  /// APAL leg's knee-only record locks its hip at the paper's -10 deg.
  int locked_joints = 0;
  Eigen::VectorXd locked_at_rad;
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

/// Minimises the criterion + a penalty on the limits' violations by Nelder-Mead from `restarts`
/// random starts about the middle of each moving joint's range (0 without one), all from
/// options.seed; keeps the best feasible end point, and if none is feasible (or a peak falls
/// between the optimiser's samples) shrinks the harmonics until it is. Deterministic. Throws
/// std::invalid_argument on bad options, limits or sizes.
ExcitationDesign designExcitation(const ExcitationOptions& options, const Robot& robot, const Eigen::VectorXd& theta_nominal,
                                  const ExcitationLimits& limits);

}  // namespace exoid::ident
