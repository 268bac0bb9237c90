#pragma once
// How much an LS estimate depends on the band chosen from the data, for any leg: every record
// whose band was chosen refitted with its cutoff a quarter wider, the change in standard errors of
// the fit (the errors-in-variables bias a wider band would add, measured).
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/model/robot.hpp"
#include "exoid/ident/signals/band.hpp"
#include "exoid/ident/signals/preprocess.hpp"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace exoid::experiments {

struct BandSensitivity {
  double factor = 0.0;                ///< the cutoffs' factor
  std::vector<std::string> names;     ///< the robot's parameters
  Eigen::VectorXd shift_se;           ///< per parameter, (x_wider - x) / std_err
  std::vector<std::string> over_one;  ///< parameters moved by more than one standard error
};

/// data[k] processed as signals[k] (bands[k]: the band chosen from it, if any; with
/// derivative_follows, the derivative's cutoff was chosen with it and follows the wider one); x:
/// the LS estimate of robot's parameters from those rows, std_err its reported errors. None when
/// no band was chosen.
std::optional<BandSensitivity> bandSensitivity(const std::vector<ident::Dataset>& data, const std::vector<ident::SignalOptions>& signals,
                                               const std::vector<std::optional<ident::BandChoice>>& bands, bool derivative_follows,
                                               const ident::Robot& robot, const Eigen::VectorXd& x, const Eigen::VectorXd& std_err);

/// The line identify prints, and a warning line when a parameter moved by more than one error.
std::vector<std::string> describe(const BandSensitivity& s);
nlohmann::json toJson(const BandSensitivity& s);

}  // namespace exoid::experiments
