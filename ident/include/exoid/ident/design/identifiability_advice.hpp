#pragma once
// An identifiability report in words a user can act on: which parameters a record leaves
// undetermined or poorly determined, which other parameter each is confused with, and what
// motion would separate them.
#include "exoid/ident/design/identifiability.hpp"
#include "exoid/ident/model/robot.hpp"

#include <string>
#include <vector>

namespace exoid::ident {

struct AdviceOptions {
  double poor_relative_std = 0.10;  ///< a parameter is "poorly determined" above this relative std
  /// Without a reference (relative std NaN): "poorly determined" when this much of its column is
  /// explained by the others (R^2; 0.95 inflates its std 4.5x over an orthogonal column's).
  double poor_collinearity = 0.95;
  double poor_condition = 100.0;    ///< the regressor is "poorly conditioned" above this (scaled)
};

/// Sentences about the report of regressor H, whose columns are robot's parameters `params`
/// (indices into robot.names()). Names the column each parameter is most nearly parallel to, and
/// the motion that informs its kind.
std::vector<std::string> identifiabilityAdvice(const Eigen::MatrixXd& H, const IdentifiabilityReport& report, const Robot& robot,
                                               const std::vector<int>& params, const AdviceOptions& options = {});

}  // namespace exoid::ident
