#pragma once
// Least squares of any chain's base parameters from its processed rows, with standard errors and
// the physically consistent estimate beside it.
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/ident/model/chain.hpp"
#include "exoid/ident/model/robot.hpp"
#include "exoid/ident/signals/processing.hpp"
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
  /// Standard errors of beta from its own residuals: Newey and West's covariance
  /// (standard_errors.hpp), each record one channel, a sample's dof equations one step (the
  /// filtered rows' residuals are correlated in time and across joints: sigma^2 (Wb' Wb)^-1
  /// underestimated the spread of 50 simulated leg3 records 1.5-2.1x).
  Eigen::VectorXd std_error;
  Eigen::MatrixXd covariance;  ///< of beta, the same estimate
  LsResult ls;
  std::optional<ConsistentFit> consistent;  ///< when asked and LS is usable (full rank)
  Eigen::Index rows = 0;
};

/// Fits the record's rows in the robot's parameters; phi_start (standard parameters,
/// e.g. the model file's nominal ones) starts the consistent fit. Throws std::invalid_argument
/// on sizes that disagree.
ChainEstimate estimateChain(const Robot& robot, const RecordRows& record, const Eigen::VectorXd& phi_start,
                            const ChainEstimateOptions& options = {});

}  // namespace exoid::ident
