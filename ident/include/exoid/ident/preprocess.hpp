#pragma once
// From a recorded dataset to the signals the regressor needs: velocities and accelerations by
// differentiation (or from recorded columns), zero-phase low-pass filtering (paper Sec. 3).
#include "exoid/ident/dataset.hpp"
#include "exoid/ident/regressor.hpp"
#include "exoid/ident/signals.hpp"

namespace exoid::ident {

struct SignalOptions {
  /// How qd and qdd are computed from the angles. Paper: forward differences.
  Differentiation differentiation = Differentiation::kForward;
  /// Use recorded qd_* / qdd_* columns instead of differentiating, when the dataset has them.
  bool use_recorded_derivatives = true;
  /// Zero-phase Butterworth low-pass (filtfilt) of angles, velocities and accelerations. Paper: on.
  bool filter = true;
  /// Butterworth order of one pass (forward-backward doubles it). Range 1..8. Default 2
  /// (the paper does not say).
  int filter_order = 2;
  /// -3 dB cutoff of one pass in Hz. Range (0, fs/2). Paper: 10 Hz.
  double cutoff_hz = 10.0;
  /// Filter the measured torques with the same filter (paper: "all measured ... signals").
  bool filter_torque = true;
  /// Seconds dropped at each end after filtering and differentiating, where the filter's edge
  /// transient (odd padding only approximates the unseen signal) and one-sided differences
  /// dominate: twice-differentiated edges are off by tens of percent. Negative = automatic:
  /// 3 / cutoff_hz when filtering (0.3 s at 10 Hz, about five time constants of the
  /// forward-backward 2nd-order filter), else 2 samples. The paper does not say.
  double edge_trim_s = -1.0;
  /// The trim in samples for a record sampled at sample_rate_hz.
  long edgeTrimSamples(double sample_rate_hz) const;
  void validate() const;  ///< throws std::invalid_argument naming the field
};

/// Angles are filtered, differentiated, the velocity filtered, differentiated again and the
/// acceleration filtered ("all measured and computed signals"). Recorded derivatives, when used,
/// are filtered too if filtering is on. Then edge_trim_s is dropped at both ends; throws
/// std::invalid_argument if fewer than 20 samples would remain.
JointSignals prepareSignals(const Dataset& d, const SignalOptions& options);

/// Rows [trim, size - trim) of every signal. Throws std::invalid_argument if fewer than 20 remain.
JointSignals trimEdges(const JointSignals& s, Eigen::Index trim);

/// The signals exactly as recorded, using the dataset's qd/qdd columns (throws if absent).
JointSignals recordedSignals(const Dataset& d);

}  // namespace exoid::ident
