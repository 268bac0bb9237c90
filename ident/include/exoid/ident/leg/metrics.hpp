#pragma once
// Scores: validation torque error and parameter error against a truth vector.
#include "exoid/ident/leg/regressor.hpp"

#include <Eigen/Core>

#include <cstdint>

namespace exoid::ident {

/// Statistics of |measured - predicted| (N m), as the paper reports them (mean +- std).
struct TorqueErrorStats {
  double mean_abs = 0.0;
  double std_abs = 0.0;  ///< population std of |error|
  double rms = 0.0;
  double max_abs = 0.0;
};
TorqueErrorStats torqueError(const Eigen::Ref<const Eigen::VectorXd>& measured,
                             const Eigen::Ref<const Eigen::VectorXd>& predicted);

struct ParamError {
  Eigen::VectorXd abs;  ///< estimate - truth
  Eigen::VectorXd rel;  ///< (estimate - truth) / |truth|; 0 where truth is 0 and estimate equal
  /// ||estimate - truth||_2 / ||truth||_2 over parameters in different units: dominated by the
  /// largest ones (Mxt alone is ~60 % of ||X||^2 for the APAL leg), so it hides errors in the
  /// small ones (friction). Reported as "norm (Mxt-dominated)"; use rel and the torque-space score.
  double norm_rel = 0.0;
  double max_abs_rel = 0.0;  ///< max |rel|
};
/// Throws std::invalid_argument on size mismatch or an all-zero truth.
ParamError paramError(const Eigen::Ref<const Eigen::VectorXd>& estimate,
                      const Eigen::Ref<const Eigen::VectorXd>& truth);

/// The fixed validation set of the torque-space score: kValidationStates exact states drawn
/// uniformly (xoshiro256**, seed kValidationSeed) over the leg's working range, hip -90..+30 deg,
/// knee 0..110 deg, velocities +-3 rad/s, accelerations +-30 rad/s^2 on each joint: richer than
/// any single training record, so every parameter moves the predicted torque. Not a record: the
/// states are independent draws (t_s is the index).
inline constexpr int kValidationStates = 4000;
inline constexpr std::uint64_t kValidationSeed = 20261201;
JointSignals validationStates();

/// Torque-space error per joint: ||Y_j (x - x*)|| / ||Y_j x*|| over validationStates(), Y_j the
/// joint's regressor rows: a parameter error weighed by what it does to the predicted torque.
struct TorqueSpaceError {
  double hip = 0.0;
  double knee = 0.0;
};
TorqueSpaceError torqueSpaceError(const ParamVector& estimate, const ParamVector& truth, const LegConstants& c);

}  // namespace exoid::ident
