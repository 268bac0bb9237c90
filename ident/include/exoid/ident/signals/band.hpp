#pragma once
// The processing band chosen from the record itself: Gautier and Janot's practice (a band a few
// times the motion's, no wider), with the errors-in-variables limit measured, not assumed.
//
// Least squares over parallel-filtered rows is exact on exact data whatever the band, and a wider
// band brings the harmonics that separate the regressor's columns (gravity from inertia on a sine
// motion). It also brings whatever the columns carry that the measured torque does not follow:
// differentiated encoder noise, angle motion the torque does not drive (a motor-side encoder
// inside a gear's backlash or compliance, structural modes). That content attenuates the
// estimates towards zero (errors-in-variables). So the band goes as wide as the torque follows
// the states:
//
// 1. The motion's bandwidth f_m: the frequency below which `motion_fraction` of the angles'
//    (mean-removed) variance lies, every joint's power pooled (Welch, 2 s segments; a joint held
//    still, whose angle is encoder noise, does not set it).
// 2. A pilot fit: least squares over every joint's equation, parallel processing at pilot_factor x f_m.
// 3. The consistency scan: the torque the pilot predicts from the measured states (the regressor
//    of the unfiltered states) against the torque measured, in bands of scan_band_hz from f_m up
//    (Welch; every joint's power pooled, as the stacked fit sees them). The band ends where the
//    prediction's amplitude first exceeds inconsistency_ratio x the measurement's: there at
//    least 1 - 1 / ratio^2 (3/4 at 2) of the columns' power is foreign to the torque.
// 4. cutoff = that frequency, at most max_factor x f_m; the derivative pre-filter at
//    derivative_factor x cutoff (its (f / fd)^8 distortion of the motion at the cutoff is
//    (1/5)^8 = 2.6e-6: exact data stay exact); decimation fs / (5 cutoff).
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/signals/preprocess.hpp"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace exoid::ident {

struct BandRule {
  /// Share of the angles' variance below the motion's bandwidth. Range (0.5, 1). Default 0.99:
  /// the motion itself, not the small harmonics a nonlinear response adds to it.
  double motion_fraction = 0.99;
  /// Pilot cutoff = pilot_factor x f_m. Range >= 1. Default 1.5.
  double pilot_factor = 1.5;
  /// Width of the scanned bands, Hz. Range > 0. Default 1 Hz (two bins of the 2 s Welch segments).
  double scan_band_hz = 1.0;
  /// Predicted / measured torque amplitude above which a band is inconsistent. Range > 1. Default 2.
  double inconsistency_ratio = 2.0;
  /// The cutoff is at most max_factor x f_m ("a few times the motion's band"). Range >= 1. Default 5.
  double max_factor = 5.0;
  /// Derivative pre-filter = derivative_factor x cutoff. Range >= 2. Default 5.
  double derivative_factor = 5.0;
  /// The record's joints above this one are held by a lock, not their motors (a segmental
  /// strategy's stage, e.g. the APAL leg's knee record with its hip fixed): the pilot fits and
  /// the scan reads the equations of joints first_moving_joint.. only. >= 0.
  Eigen::Index first_moving_joint = 0;
  /// The pilot fit and the consistency scan read the record's central pilot_max_samples at most
  /// (default 2^17: 131 s at 1 kHz, 65 of the scan's 2 s Welch segments; never fewer than 24 /
  /// f_m seconds, so the pilot's edge trims keep most of it): a 1000 s log's band then costs what a
  /// two-minute one's does. The motion's bandwidth is always read from the whole record.
  /// Range >= 0; 0 = the whole record.
  Eigen::Index pilot_max_samples = Eigen::Index{1} << 17;
  void validate() const;  ///< throws std::invalid_argument naming the field
};

/// One scanned band: the torque RMS the pilot predicts there and the one measured (N m, joints pooled).
struct BandScan {
  double from_hz = 0.0, to_hz = 0.0;
  double predicted_rms_Nm = 0.0, measured_rms_Nm = 0.0;
  double ratio() const;  ///< predicted / measured amplitude (1 when both are zero)
};

struct BandChoice {
  std::vector<std::string> joints;            ///< the record's joints
  Eigen::VectorXd joint_motion_bandwidth_hz;  ///< one per joint
  double motion_bandwidth_hz = 0.0;  ///< f_m (the joints' power pooled)
  /// The lowest cutoff the record's length allows: its edge trims (3 / cutoff each) keep half of it.
  double record_floor_hz = 0.0;
  double pilot_cutoff_hz = 0.0;
  Eigen::Index samples = 0, pilot_samples = 0;  ///< the record's, and the pilot's (its central window)
  std::vector<BandScan> scan;  ///< every band scanned, in order (the last is the inconsistent one, if any)
  double cutoff_hz = 0.0;
  double derivative_cutoff_hz = 0.0;
  int decimation = 1;
  /// "consistency" (the first inconsistent band), "motion" (inconsistent right above the motion, or
  /// above the record's floor: the band stops there), "cap" (max_factor f_m), "nyquist" (the
  /// sampling rate's limit), "length" (the record's floor is above the cap).
  std::string limited_by;
  double motion_fraction = 0.0, max_factor = 0.0;  ///< the rule's, for describe()
  /// One line for a person: the numbers above and the reason.
  std::string describe() const;
};

/// The motion's bandwidth of record d: the frequency below which `fraction` (in (0.5, 1)) of the
/// angles' mean-removed variance lies, every joint's power pooled (Welch, 2 s segments).
double motionBandwidth(const Dataset& d, double fraction = 0.99);

/// The torque a pilot fit predicts from the measured states along the record it is given (N x k)
/// and the torque measured that it is compared with (N x k): the model's part of chooseBand. The
/// record is the pilot's window of the one whose band is chosen (BandRule::pilot_max_samples);
/// the pilot options are parallel processing at the pilot's cutoff.
struct PilotTorques {
  Eigen::MatrixXd predicted_Nm, measured_Nm;
};
using PilotFit = std::function<PilotTorques(const Dataset& record, const SignalOptions& pilot)>;
/// The band of record d (parallel processing; `base` supplies the other options), the robot's
/// pilot given as a function (processing.hpp's chooseBand gives it). Throws
/// std::invalid_argument for a record sampled below 20 Hz or too short to choose a band, and as
/// the processing does (bad options).
BandChoice chooseBandWith(const Dataset& d, const SignalOptions& base, const BandRule& rule, const PilotFit& pilot_fit);

/// The derivative pre-filter for a cutoff: rule.derivative_factor x cutoff_hz, or 0 (none) when
/// that is at or above the Nyquist frequency of sample_rate_hz.
double derivativeCutoffFor(double cutoff_hz, double sample_rate_hz, const BandRule& rule = {});

/// base with the choice's cutoff (and derivative cutoff, when base leaves it to the data) in place
/// of the ones to be chosen (SignalOptions::cutoff_from_data, derivative_cutoff_from_data).
SignalOptions withBand(const SignalOptions& base, const BandChoice& choice);

}  // namespace exoid::ident
