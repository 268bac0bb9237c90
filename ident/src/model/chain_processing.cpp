#include "exoid/ident/model/chain_processing.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/ident/model/chain_regressor.hpp"
#include "exoid/ident/signals/signals.hpp"

#include <limits>
#include <stdexcept>

namespace exoid::ident {

namespace {

ChainBaseMotion baseAt(const ChainModel& model, const JointSignals& s, Eigen::Index i) {
  if (s.base.rows() == 0) return ChainBaseMotion::still(model);
  ChainBaseMotion b;
  b.specific_force_mps2 = Eigen::Vector3d(s.base(i, 0), 0.0, s.base(i, 1));
  b.omega_radps = Eigen::Vector3d(0.0, s.base(i, 2), 0.0);
  b.alpha_radps2 = Eigen::Vector3d(0.0, s.base(i, 3), 0.0);
  return b;
}

void checkJoints(const JointSignals& s, const ChainModel& model) {
  s.validate();
  if (s.q_rad.cols() != model.dof()) {
    throw std::invalid_argument("chain '" + model.name + "' has " + core::toText(model.dof()) + " joints; the signals have " +
                                core::toText(s.q_rad.cols()));
  }
}

// Every joint's regressor side by side, then the torques: N x (dof p + dof), one row per sample,
// so that one filter pass treats every column alike.
Eigen::MatrixXd sideBySide(const ChainModel& model, const JointSignals& s) {
  checkJoints(s, model);
  const Eigen::Index dof = model.dof(), p = model.standardParameterCount();
  Eigen::MatrixXd all(s.size(), dof * p + dof);
  ChainRegressorWorkspace work;
  Eigen::MatrixXd Y(dof, p);
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    chainRegressorInto(model, s.q_rad.row(i).transpose(), s.qd_radps.row(i).transpose(), s.qdd_radps2.row(i).transpose(),
                       baseAt(model, s, i), work, Y);
    for (Eigen::Index j = 0; j < dof; ++j) all.row(i).segment(j * p, p) = Y.row(j);
  }
  all.rightCols(dof) = s.tau_Nm;
  return all;
}

// Rows first, first + r, ... <= last of a side-by-side matrix, stacked joint by joint.
ChainRecord stackRows(const Eigen::MatrixXd& all, const Eigen::VectorXd& t_s, Eigen::Index dof, Eigen::Index p, Eigen::Index first,
                      Eigen::Index last, int r) {
  const Eigen::Index m = last < first ? 0 : (last - first) / r + 1;
  ChainRecord out;
  out.dof = dof;
  out.W.resize(m * dof, p);
  out.y.resize(m * dof);
  out.t_s.resize(m);
  out.record_rows = {m * dof};
  for (Eigen::Index k = 0; k < m; ++k) {
    const Eigen::Index i = first + k * r;
    out.t_s[k] = t_s[i];
    for (Eigen::Index j = 0; j < dof; ++j) {
      out.W.row(k * dof + j) = all.row(i).segment(j * p, p);
      out.y[k * dof + j] = all(i, dof * p + j);
    }
  }
  return out;
}

void checkRecordLength(Eigen::Index n, Eigen::Index trim, int r) {
  if ((n - 2 * trim + r - 1) / r < 20 || n - 2 * trim < 20) {
    throw std::invalid_argument("record too short: " + core::toText(n) + " samples, trimmed by " + core::toText(trim) +
                                " at each end (the filter's edge transients) and decimated by " + core::toText(r) +
                                ", leave fewer than 20 rows");
  }
}

}  // namespace

ChainRecord chainRows(const ChainModel& model, const JointSignals& s) {
  const Eigen::MatrixXd all = sideBySide(model, s);
  return stackRows(all, s.t_s, model.dof(), model.standardParameterCount(), 0, s.size() - 1, 1);
}

ChainRecord processChainRecord(const Dataset& d, const ChainModel& model, const SignalOptions& options,
                               std::optional<BandChoice>* chosen, const BandRule& rule) {
  model.validate();
  d.requireJoints(model.jointNames(), "model '" + model.name + "'");
  if (chosen) chosen->reset();
  if (options.processing == Processing::kPaper) return chainRows(model, prepareSignals(d, options));
  SignalOptions o = options;
  if (o.cutoff_from_data && o.filter) {
    const BandChoice band = chooseChainBand(d, model, o, rule);
    if (chosen) *chosen = band;
    o = withBand(o, band);
  } else {
    o = resolveSignalOptions(d, LegConstants{}, o);  // no band to choose: only the derivative pre-filter's rule
  }
  const double fs = 1.0 / d.sampleInterval_s();
  o.validateFor(fs);
  const Eigen::Index trim = o.edgeTrimSamples(fs);
  const int r = o.decimationFactor(fs);
  checkRecordLength(d.size(), trim, r);
  Eigen::MatrixXd all = sideBySide(model, differentiatedStates(d, o));
  if (o.filter) filtfiltInPlace(butterworthLowpass(o.filter_order, o.cutoff_hz, fs), all);
  return stackRows(all, d.t_s, model.dof(), model.standardParameterCount(), trim, d.size() - 1 - trim, r);
}

BandChoice chooseChainBand(const Dataset& d, const ChainModel& model, const SignalOptions& base, const BandRule& rule) {
  d.requireJoints(model.jointNames(), "model '" + model.name + "'");
  const Eigen::Index dof = model.dof(), first = rule.first_moving_joint;
  if (first >= dof) {
    throw std::invalid_argument("band rule: first_moving_joint " + core::toText(first) + " of a " + core::toText(dof) + "-joint model");
  }
  const BaseParameters bp = baseParameters(model);
  return chooseBandWith(d, base, rule, [&](const Dataset& record, const SignalOptions& pilot) {
    const ChainRecord rows = processChainRecord(record, model, pilot);
    // The equations of joints first.. (all when first = 0): the locked joints' torque is the lock's.
    const std::vector<Eigen::Index> fit_rows = rows.rowsOfJointsFrom(first);
    LsOptions ls;
    ls.max_condition = std::numeric_limits<double>::max();  // a pilot: its prediction is used, not its parameters
    const Eigen::VectorXd beta = solveLeastSquares(bp.baseRegressor(rows.W(fit_rows, Eigen::all)), rows.y(fit_rows), ls).x;
    const ChainRecord at_states = chainRows(model, differentiatedStates(record, pilot));
    const Eigen::VectorXd stacked = bp.baseRegressor(at_states.W) * beta;
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> predicted(
        stacked.data(), at_states.samples(), dof);
    PilotTorques t;
    t.predicted_Nm = predicted.rightCols(dof - first);
    t.measured_Nm = record.tau_Nm.rightCols(dof - first);
    return t;
  });
}

ChainRecord stackChainRecords(const std::vector<ChainRecord>& records) {
  if (records.empty()) throw std::invalid_argument("stackChainRecords: no records");
  Eigen::Index rows = 0;
  for (const ChainRecord& r : records) {
    if (r.dof != records.front().dof || r.W.cols() != records.front().W.cols()) {
      throw std::invalid_argument("stackChainRecords: records of different models");
    }
    rows += r.W.rows();
  }
  ChainRecord out;
  out.dof = records.front().dof;
  out.W.resize(rows, records.front().W.cols());
  out.y.resize(rows);
  out.t_s.resize(rows / out.dof);
  Eigen::Index at = 0, at_t = 0;
  for (const ChainRecord& r : records) {
    out.record_rows.insert(out.record_rows.end(), r.record_rows.begin(), r.record_rows.end());
    out.W.middleRows(at, r.W.rows()) = r.W;
    out.y.segment(at, r.y.size()) = r.y;
    out.t_s.segment(at_t, r.t_s.size()) = r.t_s;
    at += r.W.rows();
    at_t += r.t_s.size();
  }
  return out;
}

}  // namespace exoid::ident
