#pragma once
// The processing band chosen from the record itself: Gautier and Janot's practice (a band a few
// times the motion's, no wider), with the errors-in-variables limit measured, not assumed.
//
// Least squares over the parallel-filtered rows is exact on exact data whatever the band, so a
// wider band only adds rows of information... and whatever the regressor columns carry that the
// measured torque does not follow: differentiated encoder noise, angle motion the torque does not
// drive (a motor-side encoder inside a gear's backlash or compliance, structural modes). That
// content attenuates the estimates towards zero (errors-in-variables), more the wider the band.
// So the band is widened only while the estimates stay put:
//
// 1. The motion's bandwidth f_m: the frequency below which `motion_fraction` of each angle's
//    (mean-removed) variance lies, the larger of the two joints (Welch, 2 s segments). Angles are
//    the cleanest channels a rig records; their spectrum falls steeply past the motion.
// 2. A ladder of cutoffs f_m, ratio f_m, ratio^2 f_m, ... up to max_factor f_m: at each, least
//    squares over both equations (parallel processing) and its standard errors from its own
//    residuals (Newey-West, standard_errors.hpp).
// 3. The cutoff is the last rung whose estimate is within `max_shift_se` of its own standard
//    errors of the first rung's on every parameter: the bias a wider band adds stays below the
//    noise. On exact data every rung agrees, and the band is the widest.
// 4. The derivative pre-filter at derivative_factor x cutoff (its (f / fd)^8 distortion of the
//    motion at the cutoff is (1/5)^8 = 2.6e-6: exact data stay exact); decimation fs / (5 cutoff).
#include "exoid/ident/dataset.hpp"
#include "exoid/ident/preprocess.hpp"
#include "exoid/ident/regressor.hpp"

#include <optional>
#include <string>
#include <vector>

namespace exoid::ident {

struct BandRule {
  /// Share of each angle's variance below the motion's bandwidth. Range (0.5, 1). Default 0.99:
  /// the motion itself, not the small harmonics a nonlinear response adds to it.
  double motion_fraction = 0.99;
  /// Ratio between successive cutoffs of the ladder. Range (1, 4]. Default 1.25.
  double ladder_ratio = 1.25;
  /// The cutoff is at most max_factor x f_m ("a few times the motion's band"). Range >= 1. Default 5.
  double max_factor = 5.0;
  /// A rung is kept while no parameter moved from the first rung's estimate by more than this many
  /// of its standard errors. Range > 0. Default 1: the bias stays below the noise.
  double max_shift_se = 1.0;
  /// Derivative pre-filter = derivative_factor x cutoff. Range >= 2. Default 5.
  double derivative_factor = 5.0;
  void validate() const;  ///< throws std::invalid_argument naming the field
};

/// One rung of the ladder.
struct BandRung {
  double cutoff_hz = 0.0;
  Eigen::VectorXd x;         ///< LS over both equations
  Eigen::VectorXd std_err;   ///< its standard errors (residual-based); +inf where not identifiable
  /// max over parameters of |x - x_first| / std_err (0 on the first rung).
  double max_shift_se = 0.0;
  int worst_param = -1;      ///< where max_shift_se was attained
};

struct BandChoice {
  Eigen::Vector2d joint_motion_bandwidth_hz = Eigen::Vector2d::Zero();
  double motion_bandwidth_hz = 0.0;  ///< f_m
  std::vector<BandRung> ladder;      ///< every rung tried, in order (the last may be the one refused)
  /// The lowest cutoff the record's length allows: its edge trims (3 / cutoff each) keep half of it.
  double record_floor_hz = 0.0;
  double cutoff_hz = 0.0;
  double derivative_cutoff_hz = 0.0;
  int decimation = 1;
  /// "drift" (the next rung moved an estimate by more than the rule allows), "cap" (max_factor
  /// f_m reached), "nyquist" (the sampling rate's limit reached first).
  std::string limited_by;
  double motion_fraction = 0.0, max_factor = 0.0, max_shift_se = 0.0;  ///< the rule's, for describe()
  /// One line for a person: the numbers above and the reason.
  std::string describe() const;
};

/// The band of record d (parallel processing; `base` supplies the other options). Throws
/// std::invalid_argument as processRecord does (too short, bad options).
BandChoice chooseBand(const Dataset& d, const LegConstants& c, const SignalOptions& base, const BandRule& rule = {});

/// base with the choice's cutoff, derivative cutoff and decimation in place of the ones to be
/// chosen (SignalOptions::cutoff_from_data, derivative_cutoff_from_data).
SignalOptions withBand(const SignalOptions& base, const BandChoice& choice);

}  // namespace exoid::ident
