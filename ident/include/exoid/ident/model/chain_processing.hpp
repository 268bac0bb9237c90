#pragma once
// Any serial chain's record, from the dataset to the rows an estimator fits: the 2-link leg's
// processing (preprocess.hpp: the paper's, or parallel filtering and decimation, the band chosen
// from the data) with the chain's regressor in place of the hand-written one.
#include "exoid/ident/signals/band.hpp"
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/model/chain.hpp"
#include "exoid/ident/signals/preprocess.hpp"

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace exoid::ident {

/// Stacked equations: sample k's equation of joint j is row k * dof + j (time order, as RLS
/// wants it); columns are the model's standard parameters.
struct ChainRecord {
  Eigen::MatrixXd W;
  Eigen::VectorXd y;  ///< the torques, processed like the rows
  Eigen::VectorXd t_s;  ///< each sample's time (one per dof rows)
  Eigen::Index dof = 0;
  /// Rows of each record stacked in, in order (one entry for a single record): the residuals'
  /// correlation is estimated within a record, never across a seam.
  std::vector<Eigen::Index> record_rows;
  Eigen::Index samples() const { return dof ? y.size() / dof : 0; }
  /// The rows of the equations of joints first .. dof - 1, in time order (a record whose joints
  /// above `first` are locked: the lock, not the motor, carries theirs).
  std::vector<Eigen::Index> rowsOfJointsFrom(Eigen::Index first) const {
    std::vector<Eigen::Index> rows;
    rows.reserve(static_cast<std::size_t>(samples() * (dof - first)));
    for (Eigen::Index k = 0; k < samples(); ++k) {
      for (Eigen::Index j = first; j < dof; ++j) rows.push_back(k * dof + j);
    }
    return rows;
  }
};

/// The rows of signals as they are (no processing). Base motion, when s.base has rows, as the
/// 2-link leg's IMU columns: specific force (f_x, 0, f_z), pitch rate and acceleration about y, in
/// the chain's base frame.
ChainRecord chainRows(const ChainModel& model, const JointSignals& s);

/// The record processed by o.processing (kPaper: the regressor of the filtered signals;
/// kParallel: rows from the states, then rows and torques through the same zero-phase filter,
/// trimmed and decimated). The choices o leaves to the data are made first (chooseChainBand);
/// chosen, when given, receives the band. Throws std::invalid_argument when the dataset's joints
/// are not the model's, or as processRecord does.
/// rule: the band rule (e.g. first_moving_joint for a record whose upper joints are locked).
ChainRecord processChainRecord(const Dataset& d, const ChainModel& model, const SignalOptions& o,
                               std::optional<BandChoice>* chosen = nullptr, const BandRule& rule = {});

/// chooseBand's rule with the chain's pilot (least squares in base parameters over every joint,
/// or over joints rule.first_moving_joint.. when the joints above are locked).
BandChoice chooseChainBand(const Dataset& d, const ChainModel& model, const SignalOptions& base, const BandRule& rule = {});

/// Several records' rows as one (each processed on its own). Throws for none or mixed dof.
ChainRecord stackChainRecords(const std::vector<ChainRecord>& records);

}  // namespace exoid::ident
