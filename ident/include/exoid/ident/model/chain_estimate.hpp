#pragma once
// Least squares of any chain's base parameters from its processed rows, with standard errors and
// the physically consistent estimate beside it.
#include "exoid/ident/least_squares.hpp"
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/ident/model/chain.hpp"
#include "exoid/ident/model/chain_processing.hpp"
#include "exoid/ident/model/consistent_fit.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace exoid::ident {

struct ChainEstimateOptions {
  LsOptions ls;
  /// Also the physically consistent estimate (consistent_fit.hpp), from phi_start.
  bool consistent = true;
  ConsistentFitOptions consistent_fit;
};

struct ChainEstimate {
  std::vector<std::string> names;  ///< the base parameters' readable combinations
  Eigen::VectorXd beta;            ///< least squares
  /// Standard errors of beta: sigma^2 (Wb' Wb)^-1 with sigma^2 = RSS / (rows - rank), the
  /// rows' errors taken as independent and of one variance (the filtered, decimated rows are
  /// close to it; a coloured residual makes these optimistic).
  Eigen::VectorXd std_error;
  LsResult ls;
  std::optional<ConsistentFit> consistent;  ///< when asked and LS is usable (full rank)
  Eigen::Index rows = 0;
};

/// Fits the record's rows in the base parameters of `base`; phi_start (standard parameters,
/// e.g. the model file's nominal ones) starts the consistent fit. Throws std::invalid_argument
/// on sizes that disagree.
ChainEstimate estimateChain(const ChainModel& model, const BaseParameters& base, const ChainRecord& record,
                            const Eigen::VectorXd& phi_start, const ChainEstimateOptions& options = {});

}  // namespace exoid::ident
