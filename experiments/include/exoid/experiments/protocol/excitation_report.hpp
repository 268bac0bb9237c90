#pragma once
// How well a fit's records excite its parameters, for any leg: the condition number of the
// column-scaled regressor and each column's R^2 on the others (1 - 1 / [(Hs^T Hs)^-1]_jj for unit
// columns): a model error along a column is amplified 1 / sqrt(1 - R^2) times in its parameter.
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/estimators/methods.hpp"

#include <string>
#include <utility>
#include <vector>

namespace exoid::experiments {

struct Excitation {
  double condition = 0.0;
  std::vector<std::pair<std::string, double>> collinear;  ///< (parameter, R^2) with R^2 > 0.95, worst first
};

/// From the least-squares fit of the parameters `names` (its factor's condition and collinearity).
Excitation excitationOf(const ident::LsResult& ls, const std::vector<std::string>& names);
/// The same from a least-squares estimate (Method::kLs) of `names`, e.g. a segmental stage's.
Excitation excitationOf(const ident::Estimate& ls, const std::vector<std::string>& names);

/// "excitation of <of>: condition number ...; nearly collinear ...", with `advice` (what would
/// separate them) when the condition exceeds 100 or a column is nearly collinear.
std::string describe(const Excitation& e, const std::string& of, const std::string& advice);

}  // namespace exoid::experiments
