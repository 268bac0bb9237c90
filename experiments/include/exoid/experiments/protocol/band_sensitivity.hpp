#pragma once
// How much an LS estimate depends on the band chosen from the data, for any leg: every record
// whose band was chosen refitted with its cutoff a quarter wider, the change in standard errors of
// the fit (the errors-in-variables bias a wider band would add, measured).
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/model/robot.hpp"
#include "exoid/ident/signals/band.hpp"
#include "exoid/ident/signals/preprocess.hpp"
#include "exoid/ident/signals/processing.hpp"

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
  bool on_windows = false;            ///< a record longer than its band's pilot window compared on it
};

/// The refit behind it: data[k] processed as signals[k] (bands[k]: the band chosen from it, if
/// any; with derivative_follows, the derivative's cutoff was chosen with it and follows the wider
/// one) gave `fitted` (stacked, one record each). Every chosen cutoff x factor, LS refitted. A
/// record longer than its band's pilot window is compared on that central window (its rows of
/// `fitted` there, against the window processed in the wider band): `narrow` is their LS estimate,
/// none when every record is compared whole (the fit's own estimate is the narrow one). Needs only
/// the records, so it can run beside the fit. None when no band was chosen.
struct BandRefit {
  double factor = 1.25;  ///< a quarter wider
  Eigen::VectorXd wider;
  std::optional<Eigen::VectorXd> narrow;
};
std::optional<BandRefit> refitInAWiderBand(const std::vector<ident::Dataset>& data, const std::vector<ident::SignalOptions>& signals,
                                           const std::vector<std::optional<ident::BandChoice>>& bands, bool derivative_follows,
                                           const ident::Robot& robot, const ident::RecordRows& fitted);

/// A record's processing `used` with the cutoff chosen from it (`band`) `factor` times wider, up to
/// a fifth of the sampling rate `fs_hz`; with derivative_follows the derivative's cutoff follows
/// it. `used` itself when no band was chosen.
ident::SignalOptions widerBand(const ident::SignalOptions& used, const std::optional<ident::BandChoice>& band, bool derivative_follows,
                               double fs_hz, double factor);

/// The refit's change of each parameter from x (the LS estimate of `fitted`; the windows' when
/// the refit has one), in std_err, the estimate's reported errors.
BandSensitivity bandSensitivity(const BandRefit& refit, const ident::Robot& robot, const Eigen::VectorXd& x, const Eigen::VectorXd& std_err);

/// The line identify prints, and a warning line when a parameter moved by more than one error.
std::vector<std::string> describe(const BandSensitivity& s);
nlohmann::json toJson(const BandSensitivity& s);

}  // namespace exoid::experiments
