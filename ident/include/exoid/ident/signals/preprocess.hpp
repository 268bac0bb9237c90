#pragma once
// From a recorded dataset to the signals the regressor needs: velocities and accelerations by
// differentiation (or from recorded columns), zero-phase low-pass filtering (paper Sec. 3).
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/signals/joint_signals.hpp"
#include "exoid/ident/signals/signals.hpp"

#include <vector>

namespace exoid::ident {

/// How a record becomes the rows an estimator fits.
enum class Processing {
  /// The paper: angles, velocities, accelerations and torques each low-pass filtered, the
  /// regressor built from the filtered signals. Its nonlinear columns (sgn, products) are not the
  /// filtered columns, so even exact data give biased estimates.
  kPaper,
  /// Parallel filtering and decimation (Gautier 1997): the regressor is built from the states,
  /// then the torque and EVERY regressor column pass through the same zero-phase low-pass and are
  /// trimmed and decimated alike: filter(tau) = filter(Y) x holds exactly whenever tau = Y x,
  /// whatever the filter. Derivatives: recorded ones, else five-point central differences of the
  /// angles after a wide zero-phase pre-filter (derivative_cutoff_hz).
  kParallel,
};
const char* toString(Processing p);  ///< "paper", "parallel"

/// Whether the regressor includes the base's motion (the APAL leg's pedestal, a chain's mount) from
/// the dataset's IMU columns base_acc_x, base_acc_z (specific force at the base frame's origin, in
/// that frame: the APAL leg's hip axis, a chain's first joint's parent body; m/s^2) and
/// base_gyro_y (pitch rate, rad/s); the pitch acceleration is a recorded base_alpha_y (rad/s^2)
/// when the recorded derivatives are used, else differentiated from the gyro like the angles.
/// Parallel processing only.
enum class BaseTerms {
  kOff,   ///< a still base under gravity (the paper's model)
  kAuto,  ///< when the dataset has the three columns
  kOn,    ///< required: a dataset without them is an error
  /// when the dataset has the three columns and they predict its torque no worse: processRecord
  /// and resolveSignalOptions judge (chooseBaseTerms) and make it kAuto or kOff; unjudged, as kAuto
  kJudged,
};
const char* toString(BaseTerms b);  ///< "off", "auto", "on", "judged"
/// kAuto or kJudged: the terms whenever the dataset has the columns, unless judged otherwise.
inline bool whenPresent(BaseTerms b) { return b == BaseTerms::kAuto || b == BaseTerms::kJudged; }
/// The IMU's columns: base_acc_x, base_acc_z, base_gyro_y.
extern const char* const kBaseColumns[3];
/// True when the dataset has kBaseColumns.
bool hasBaseColumns(const Dataset& d);

struct SignalOptions {
  /// Regressor-level processing (processRecord). prepareSignals is always the paper's.
  Processing processing = Processing::kPaper;
  /// Parallel processing: keep every decimation-th row after filtering and trimming; 0 = automatic,
  /// floor(fs / (5 cutoff_hz)) (20 at 1 kHz and 10 Hz: the new Nyquist frequency is 2.5x the
  /// cutoff) when filtering, else 1; 1 = none. Range >= 0.
  int decimation = 0;
  /// Parallel processing: cutoff (Hz) of the angles' pre-filter before differentiating, order 4,
  /// zero-phase. Wide, so the motion passes unchanged ((f/fc)^8 = 4e-14 at f = 1 Hz, 50 Hz); the
  /// parallel filter removes the noise it lets through afterwards. 0 = no pre-filter.
  double derivative_cutoff_hz = 50.0;
  /// Parallel processing: base-motion terms from the IMU columns. Default kOff (the paper's
  /// model); exoid identify defaults to kAuto.
  BaseTerms base_terms = BaseTerms::kOff;
  /// Parallel processing: a record longer than this (plus two margins, parallelBlockMargin) is
  /// processed a block at a time, so memory stays bounded by the block, not the log. >= 1.
  Eigen::Index block_samples = 65536;
  /// Parallel processing of a long record: blocks processed at once, each on its own thread
  /// (0 = the machine's cores). Every block is computed alone and the blocks are stacked in
  /// order, so the result is the same bytes whatever the number. >= 0.
  int threads = 1;
  /// The decimation factor for a record sampled at sample_rate_hz.
  int decimationFactor(double sample_rate_hz) const;
  /// How qd and qdd are computed from the angles. Paper: forward differences.
  Differentiation differentiation = Differentiation::kForward;
  /// Use recorded qd_* / qdd_* columns instead of differentiating, when the dataset has them;
  /// with recorded velocities alone, the accelerations are their derivative (not the angles').
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
  /// Parallel processing: choose cutoff_hz (and with it the decimation) from the record itself
  /// (band.hpp: the motion's bandwidth and the errors-in-variables limit); cutoff_hz is then
  /// ignored. The paper's processing keeps its cutoff_hz. exoid identify's default.
  bool cutoff_from_data = false;
  /// Parallel processing: derivative_cutoff_hz = 5 x the cutoff in use (chosen or given) instead of
  /// the value above. exoid identify's default.
  bool derivative_cutoff_from_data = false;
  /// The trim in samples for a record sampled at sample_rate_hz.
  long edgeTrimSamples(double sample_rate_hz) const;
  void validate() const;  ///< throws std::invalid_argument naming the field
  /// validate(), and the filters' cutoffs below the Nyquist frequency of a record sampled at
  /// sample_rate_hz (the message says the rate, and suggests the time unit for a slow one).
  void validateFor(double sample_rate_hz) const;
};

/// Angles are filtered, differentiated, the velocity filtered, differentiated again and the
/// acceleration filtered ("all measured and computed signals"). Recorded derivatives, when used,
/// are filtered too if filtering is on. Then edge_trim_s is dropped at both ends; throws
/// std::invalid_argument if fewer than 20 samples would remain.
JointSignals prepareSignals(const Dataset& d, const SignalOptions& options);

/// Rows [trim, size - trim) of every signal. Throws std::invalid_argument if fewer than 20 remain.
JointSignals trimEdges(const JointSignals& s, Eigen::Index trim);

/// The parallel processing's full-rate states of record d: recorded derivatives, else five-point
/// differences of the angles after the derivative pre-filter (unfiltered angles and torques), and
/// the base motion from the IMU columns when o.base_terms asks for it.
JointSignals differentiatedStates(const Dataset& d, const SignalOptions& o);
/// Rows [from, to) of the same, computed from those rows alone (a long log's block with its margins).
JointSignals differentiatedStates(const Dataset& d, const SignalOptions& o, Eigen::Index from, Eigen::Index to);
/// Samples of context on each side of a block of the parallel processing: enough for the
/// pre-filter, differences and parallel filter of the block's edges to die out before its kept rows.
Eigen::Index parallelBlockMargin(const SignalOptions& o, double sample_rate_hz);
/// Throws std::invalid_argument naming the numbers when a record of n samples, trimmed by `trim`
/// at each end and decimated by r, leaves fewer than 20 rows.
void checkRecordLength(Eigen::Index n, Eigen::Index trim, int r);

}  // namespace exoid::ident
