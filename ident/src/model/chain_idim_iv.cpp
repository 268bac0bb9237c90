#include "exoid/ident/model/chain_idim_iv.hpp"

#include "exoid/core/format.hpp"

#include <stdexcept>

namespace exoid::ident {

namespace {

// The simulated (or reference) states as a record of the chain's joints, for processChainRecord.
Dataset asDataset(const ChainModel& model, const JointSignals& s, bool derivatives) {
  Dataset d;
  d.joints = model.jointNames();
  d.t_s = s.t_s;
  d.q_rad = s.q_rad;
  d.tau_Nm = s.tau_Nm;
  if (derivatives) {
    d.qd_radps = s.qd_radps;
    d.qdd_radps2 = s.qdd_radps2;
  }
  d.extra.resize(s.size(), 0);
  return d;
}

}  // namespace

Instruments chainInstruments(const ChainModel& model, const BaseParameters& base, const Eigen::VectorXd& beta,
                             const ChainClosedLoopRecord& r) {
  Instruments z;
  const ClosedLoopRun run = simulateChainClosedLoop(model, base, beta, r.controller, r.reference);
  JointSignals states = run.states;
  if (!run.ok) {
    states.t_s = r.reference.t_s;
    states.q_rad = r.reference.q_rad;
    states.qd_radps = r.reference.qd_radps;
    states.qdd_radps2 = r.reference.qdd_radps2;
    states.tau_Nm = Eigen::MatrixXd::Zero(r.reference.size(), model.dof());
    z.fixed = true;
    z.message = "instruments from the reference (the model of this iteration cannot be simulated: " + run.message + ")";
  }
  const ChainRecord rows = processChainRecord(asDataset(model, states, r.recorded_derivatives), model, r.signals);
  if (rows.y.size() != r.measured.y.size()) {
    throw std::invalid_argument("IDIM-IV: the reference has " + core::toText(r.reference.size()) +
                                " samples but the measured record's rows do not come from as many (process it with the same options)");
  }
  z.Z = base.baseRegressor(rows.W);
  z.ok = true;
  return z;
}

Estimate identifyChainIdimIv(const ChainModel& model, const BaseParameters& base, const std::vector<ChainClosedLoopRecord>& records,
                             const IvOptions& options) {
  if (records.empty()) throw std::invalid_argument("IDIM-IV: no records");
  std::vector<ChainRecord> measured;
  for (const ChainClosedLoopRecord& r : records) {
    if (r.signals.processing != Processing::kParallel || r.signals.cutoff_from_data || r.signals.derivative_cutoff_from_data) {
      throw std::invalid_argument("IDIM-IV needs each record's parallel processing with its band fixed (withBand): its instruments "
                                  "are processed like the measured rows");
    }
    measured.push_back(r.measured);
  }
  const ChainRecord stacked = stackChainRecords(measured);
  const Eigen::MatrixXd H = base.baseRegressor(stacked.W);
  return iterateInstrumentalVariables(H, stacked.y, [&](const Eigen::VectorXd& beta) {
    Instruments all;
    all.ok = true;
    all.Z.resize(H.rows(), H.cols());
    Eigen::Index row = 0;
    for (const ChainClosedLoopRecord& r : records) {
      Instruments z = chainInstruments(model, base, beta, r);
      all.Z.middleRows(row, z.Z.rows()) = z.Z;
      row += z.Z.rows();
      all.fixed = all.fixed || z.fixed;
      if (!z.message.empty()) all.message += (all.message.empty() ? "" : "; ") + z.message;
    }
    return all;
  }, options);
}

}  // namespace exoid::ident
