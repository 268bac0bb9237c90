#pragma once
// IDIM-IV for any serial chain (estimators/idim_iv.hpp explains the estimator): instruments from
// closed-loop simulations of the chain identified at the previous iteration
// (chain_closed_loop.hpp), processed exactly as the measured record was, in base parameters.
#include "exoid/ident/estimators/idim_iv.hpp"
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/ident/model/chain.hpp"
#include "exoid/ident/model/chain_closed_loop.hpp"
#include "exoid/ident/model/chain_processing.hpp"

#include <vector>

namespace exoid::ident {

/// One record as the chain's IDIM-IV needs it.
struct ChainClosedLoopRecord {
  ChainRecord measured;         ///< processChainRecord(dataset, model, signals)
  SignalOptions signals;        ///< what measured was processed with: kParallel, its band fixed (withBand)
  ChainReference reference;     ///< the controller's reference, at the record's samples
  ChainController controller;
  /// The record's velocities and accelerations were recorded (qd_/qdd_ columns) and used: the
  /// simulated ones are given to the processing too, so both take the same path.
  bool recorded_derivatives = false;
};

/// The instrument rows of a record for base parameters beta: its closed-loop simulation processed
/// like the measured record (rows aligned with `measured`), in base-regressor columns. When beta
/// cannot be simulated (M(q) not positive definite, or a joint off its reference by 1 rad), the
/// instruments come from the reference itself (perfect tracking: still free of the measurement
/// noise), fixed, said in the message.
Instruments chainInstruments(const ChainModel& model, const BaseParameters& base, const Eigen::VectorXd& beta,
                             const ChainClosedLoopRecord& record);

/// IDIM-IV over one or more records fitted together (their rows stacked): x0 = LS, then
/// x_{k+1} = IV(H, y, Z(x_k)) until each step is below options.step_tolerance standard errors.
/// Throws std::invalid_argument for no records or a record not processed in parallel.
Estimate identifyChainIdimIv(const ChainModel& model, const BaseParameters& base, const std::vector<ChainClosedLoopRecord>& records,
                             const IvOptions& options = {});

}  // namespace exoid::ident
