#pragma once
// Any robot's record, from the dataset to the rows an estimator fits (preprocess.hpp's options):
// the paper's processing (the regressor of the filtered signals), or the parallel filtering and
// decimation in the band chosen from the record (band.hpp), a long log a block at a time. One
// implementation for every leg: the robot's rows (model/robot.hpp) are all that differs.
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/model/robot.hpp"
#include "exoid/ident/signals/band.hpp"
#include "exoid/ident/signals/base_terms.hpp"
#include "exoid/ident/signals/preprocess.hpp"

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace exoid::ident {

/// A record's equations, stacked in time order: sample k's equation of joint j is row k dof + j
/// (RLS sees the record in order); the columns are the robot's parameters.
struct RecordRows {
  Eigen::MatrixXd W;
  Eigen::VectorXd y;  ///< the torques, processed like the rows
  /// Each sample's state (t, q, qd, qdd, base motion; the parallel processing's unfiltered) and its
  /// torque as processed (y by joint).
  JointSignals states;
  Eigen::Index dof = 0;
  /// Rows of each record stacked in, in order (one entry for one record): a residual's
  /// correlation is estimated within a record, never across a seam.
  std::vector<Eigen::Index> record_rows;

  Eigen::Index samples() const { return dof ? y.size() / dof : 0; }
  /// The rows of joint j's equation, in time order.
  std::vector<Eigen::Index> rowsOfJoint(Eigen::Index j) const;
  /// The rows of the equations of joints first .. dof - 1, in time order (a record whose joints
  /// above `first` are locked: the lock, not the motor, carries theirs).
  std::vector<Eigen::Index> rowsOfJointsFrom(Eigen::Index first) const;
  /// Joint j's equation rows (samples x parameters) and its torque (samples).
  Eigen::MatrixXd jointW(Eigen::Index j) const;
  Eigen::VectorXd jointY(Eigen::Index j) const;
};

/// The rows of signals as they are (no processing).
RecordRows recordRows(const Robot& robot, const JointSignals& s);

/// The record processed by o.processing: kPaper = recordRows(prepareSignals(d, o)); kParallel =
/// rows from the states, then rows and torques through the same zero-phase filter, trimmed and
/// decimated (a record longer than o.block_samples a block at a time, on o.threads: the same
/// bytes whatever the number). The choices o leaves to the data are made first
/// (resolveSignalOptions with `rule`); chosen, when given, receives the band. Throws
/// std::invalid_argument when the dataset's joints are not the robot's, or as prepareSignals does.
RecordRows processRecord(const Dataset& d, const Robot& robot, const SignalOptions& o, const BandRule& rule = {},
                         std::optional<BandChoice>* chosen = nullptr);

/// The parallel filtering and decimation of states sampled at sample_rate_hz (whatever
/// o.processing says; o's choices made): the rows processRecord gives for kParallel once it has
/// the states. Rows align with processRecord's for a record of the same length and rate (IDIM-IV's
/// instruments).
RecordRows parallelProcess(const JointSignals& states, const Robot& robot, const SignalOptions& o, double sample_rate_hz);

/// Several records' rows as one, in order: each was processed on its own (its filter, edge trims
/// and decimation), so no seam between records enters the fit. Throws std::invalid_argument for
/// none, records of different robots, or when some have base-motion states and others not.
RecordRows stackRecords(const std::vector<RecordRows>& records);

/// chooseBandWith's rule with the robot's pilot: least squares over the equations of joints
/// rule.first_moving_joint .. (every joint when 0), its torque predicted from the measured states.
BandChoice chooseBand(const Dataset& d, const Robot& robot, const SignalOptions& base, const BandRule& rule = {});

/// o with the choices it leaves to the data made for record d: the band (cutoff_from_data, parallel
/// processing, filtering on; chooseBand with `rule`), the derivative pre-filter
/// (derivative_cutoff_from_data: derivativeCutoffFor the cutoff in use) and the base-motion terms
/// (base_terms kJudged: with the IMU columns chooseBaseTerms in that band, then kAuto when kept or
/// kOff; without them kAuto). o itself when it leaves none or uses the paper's processing. chosen
/// and base_terms, when given, receive the choices made (or are reset).
SignalOptions resolveSignalOptions(const Dataset& d, const Robot& robot, const SignalOptions& o, const BandRule& rule = {},
                                   std::optional<BandChoice>* chosen = nullptr, std::optional<BaseTermsChoice>* base_terms = nullptr);

}  // namespace exoid::ident
