#pragma once
// Excitation design for any serial chain (the 2-link leg's excitation.hpp, generalised): a
// periodic finite Fourier series per joint, at rest at the period's ends, rated on the chain's
// base regressor over one period, under the joints' limits (range, speed, acceleration, the
// nominal model's torque). Same criteria, same optimiser (Nelder-Mead from seeded restarts,
// a penalty on the limits, the harmonics shrunk until the end point is feasible).
#include "exoid/core/fourier_series.hpp"
#include "exoid/ident/design/excitation.hpp"
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/ident/model/chain.hpp"

#include <Eigen/Core>

#include <string>

namespace exoid::ident {

/// One entry per joint; +infinity (or -infinity for q_min) where the robot gives no limit.
struct ChainExcitationLimits {
  Eigen::VectorXd q_min_rad, q_max_rad, qd_max_radps, qdd_max_radps2, tau_max_Nm;
  void validate(int dof) const;  ///< sizes, order, finite ranges; throws std::invalid_argument
};

struct ChainExcitationScore {
  double condition_number = 0.0;  ///< of the column-scaled base regressor over one period
  double sum_log_std = 0.0;       ///< sum of log Cramer-Rao stds (unit white noise per row)
  double worst_violation = 0.0;   ///< largest excess over a limit, relative to the limit (0 = feasible)
  std::string worst_violation_name;  ///< e.g. "qd[knee]"
};

ChainExcitationScore scoreChainExcitation(const ChainModel& model, const BaseParameters& base, const core::FourierSeries& t,
                                          const Eigen::VectorXd& phi_nominal, const ChainExcitationLimits& limits, int samples = 1000);

struct ChainExcitationDesign {
  core::FourierSeries trajectory;
  ChainExcitationScore score;  ///< on 1000 samples
  long evaluations = 0;
  int feasible_restarts = 0;
};

/// options: criterion, harmonics, f0_hz, restarts, max_evaluations, samples, seed (hip_locked
/// must be false: a chain locks no joint). Random starts about the middle of each joint's range
/// (0 for a joint without one). Deterministic. Throws std::invalid_argument on bad options.
ChainExcitationDesign designChainExcitation(const ExcitationOptions& options, const ChainModel& model, const BaseParameters& base,
                                            const Eigen::VectorXd& phi_nominal, const ChainExcitationLimits& limits);

}  // namespace exoid::ident
