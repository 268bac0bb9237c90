#pragma once
// Least squares of any chain's base parameters from its processed rows, with standard errors and
// the physically consistent estimate beside it.
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/estimators/standard_errors.hpp"
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
  /// Standard errors of beta (standard_errors.hpp): per base parameter the larger of Newey and
  /// West's from the residuals (each record a channel, the joints of a sample one step) and the
  /// block jackknife's over the records; NaN when LS is rank deficient.
  Eigen::VectorXd std_error;
  Eigen::MatrixXd covariance;  ///< of beta: Newey-West's correlations, std_error's variances
  ReportedErrors errors;       ///< both estimates and which was reported
  LsResult ls;
  Eigen::MatrixXd normal;  ///< A = Wb' Wb, the consistent fit's metric (when LS is of full rank)
  std::optional<ConsistentFit> consistent;  ///< when asked and LS is usable (full rank)
  Eigen::Index rows = 0;
};

/// Fits the record's rows in the robot's parameters; phi_start (standard parameters,
/// e.g. the model file's nominal ones) starts the consistent fit. Throws std::invalid_argument
/// on sizes that disagree.
ChainEstimate estimateChain(const Robot& robot, const RecordRows& record, const Eigen::VectorXd& phi_start,
                            const ChainEstimateOptions& options = {});

}  // namespace exoid::ident
