// One run of a chain sweep: two simulated records, every method's fit, its scores against truth.
#include "exoid/experiments/sweep/robot_sweep.hpp"

#include "exoid/core/random.hpp"
#include "exoid/experiments/commands/robot_commands.hpp"
#include "exoid/experiments/protocol/excitation_design.hpp"
#include "exoid/experiments/protocol/excitation_io.hpp"
#include "exoid/experiments/protocol/robot_loader.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/experiments/protocol/controller_io.hpp"
#include "exoid/ident/estimators/band_iv.hpp"
#include "exoid/ident/estimators/idim_iv.hpp"
#include "exoid/ident/model/base_estimate.hpp"
#include "exoid/ident/signals/processing.hpp"
#include "exoid/ident/signals/band.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>

namespace exoid::experiments {

// Named, not anonymous: the unity build puts this file beside the APAL sweep's own helpers.
namespace robot_sweep_run {

sim::ChainSimConfig recordConfig(const SweepConfig& c, const SweepCondition& cond, std::uint64_t seed) {
  sim::ChainSimConfig s;
  s.model_path = c.chain_model_path;
  s.selection = c.chain_selection;
  s.duration_s = c.base.sim.duration_s;
  s.dt_s = c.base.sim.dt_s;
  s.sensors.noise_q_deg = cond.angle_noise_deg;
  s.sensors.quantisation_deg = cond.quantisation_deg;
  s.sensors.encoder_backlash_deg = cond.encoder_backlash_deg;
  s.sensors.noise_tau_Nm = cond.torque_noise_Nm;
  s.vibration_level = cond.vibration_level;
  s.seed = seed;
  return s;
}

// Per joint: the validation record's RMS torque error (N m) and the error of the predicted
// torque against the truth's, relative to the truth's (||Wv (x - t)||_j / ||Wv t||_j).
struct JointScores {
  std::vector<double> rms_Nm, rel_to_truth;
};

JointScores scoreOn(const ident::RecordRows& v, const Eigen::MatrixXd& Wv, const Eigen::VectorXd& x, const Eigen::VectorXd& truth) {
  const Eigen::Index dof = v.dof;
  const Eigen::VectorXd residual = v.y - Wv * x, deviation = Wv * (x - truth), reference = Wv * truth;
  JointScores s;
  for (Eigen::Index j = 0; j < dof; ++j) {
    double r2 = 0.0, d2 = 0.0, t2 = 0.0;
    for (Eigen::Index k = 0; k < v.samples(); ++k) {
      const Eigen::Index row = k * dof + j;
      r2 += residual[row] * residual[row];
      d2 += deviation[row] * deviation[row];
      t2 += reference[row] * reference[row];
    }
    s.rms_Nm.push_back(std::sqrt(r2 / static_cast<double>(v.samples())));
    s.rel_to_truth.push_back(t2 > 0.0 ? std::sqrt(d2 / t2) : 0.0);
  }
  return s;
}

nlohmann::json methodJson(ident::Method m, bool usable, const std::string& message, const Eigen::VectorXd& x, const JointScores& s) {
  return {{"method", ident::toString(m)},
          {"status", usable ? "ok" : "unusable"},
          {"message", message},
          {"x", toVector(x)},
          {"val_rms_Nm", s.rms_Nm},
          {"torque_err_rel", s.rel_to_truth}};
}

// A method other than LS on the fit record's rows (iv-band and IDIM-IV on the record itself).
ident::Estimate otherEstimate(ident::Method m, const ident::Robot& robot,
                              const ident::Dataset& d, const ident::RecordRows& rec, const std::optional<ident::BandChoice>& band,
                              const ident::SignalOptions& fit_signals, const ident::MethodOptions& mo) {
  if (m == ident::Method::kIvBand) {
    const double fm = band ? band->motion_bandwidth_hz : ident::motionBandwidth(d);
    return ident::solveBandIv({ident::bandIvRows(d, robot, fit_signals, fm)}, mo.ls);
  }
  if (m == ident::Method::kIdimIv) {
    // The record's own controller (its metadata) and reference, instruments processed in its band.
    const ident::ClosedLoopRecord r = closedLoopRecord(d, "the fit record", rec, fit_signals, "");
    ident::IvOptions iv;
    iv.ls = mo.ls;
    return ident::identifyIdimIv(robot, {r}, iv);
  }
  return ident::estimate(m, rec.W, rec.y, mo);
}

}  // namespace robot_sweep_run

nlohmann::json runChainSweepRun(const SweepConfig& c, const SweepCondition& cond, std::uint64_t seed) {
  using namespace robot_sweep_run;  // this file's helpers (named, not anonymous, for the unity build)
  sim::ChainSimConfig fit_config = recordConfig(c, cond, core::deriveSeed(seed, 1));
  if (cond.trajectories == "optimised") fit_config.trajectory = c.chain_design->series;
  const sim::ChainSimResult fit = sim::simulateChain(fit_config);
  const sim::ChainSimResult check = sim::simulateChain(recordConfig(c, cond, core::deriveSeed(seed, 2)));
  const ident::Dataset d = chainDataset(fit);
  const ident::SignalOptions signals = defaultArmSignals(c.base);
  const LoadedChain loaded = loadChain(c.chain_model_path, {}, c.chain_selection);
  const ident::ChainModel& model = loaded.model;
  const ident::BaseParameters& base = loaded.base;
  const Eigen::VectorXd truth = base.combination * standardParameters(fit.chain, model);

  std::optional<ident::BandChoice> band;
  // The record's band and base-motion terms chosen from it; the check record is processed the same way.
  const ident::SignalOptions fit_signals = ident::resolveSignalOptions(d, loaded.robot, signals, c.base.band_rule, &band);
  const ident::RecordRows rec = ident::processRecord(d, loaded.robot, fit_signals);
  ident::ChainEstimateOptions eo;
  eo.ls = c.base.methods.ls;
  eo.consistent = false;
  const ident::ChainEstimate est = ident::estimateChain(loaded.robot, rec, loaded.phi, eo);
  ident::MethodOptions mo = c.base.methods;
  mo.rls_pso.pso.seed = core::deriveSeed(seed, 100);  // each run's own swarm, as the APAL protocol's
  if (!c.origin.count("identification.wide_box")) mo.wide_box_half_width = ident::psoHalfWidthFromLs(est.beta);

  const ident::RecordRows v = ident::processRecord(chainDataset(check), loaded.robot, fit_signals);
  const Eigen::MatrixXd& Wv = v.W;
  nlohmann::json j;
  j["base_parameters"] = base.names;
  j["truth"] = toVector(truth);
  j["rows"] = est.rows;
  j["condition_number"] = est.ls.condition_number;
  if (band) j["band"] = {{"cutoff_hz", band->cutoff_hz}, {"derivative_cutoff_hz", band->derivative_cutoff_hz}, {"decimation", band->decimation}};
  j["base_terms_used"] = usesBaseMotion(d, fit_signals);
  j["methods"] = nlohmann::json::array();
  for (ident::Method m : c.chain_methods) {
    if (m == ident::Method::kLs) {
      const bool usable = est.ls.rank == base.rank && est.ls.summary.status != ident::Status::kIllConditioned;
      nlohmann::json mj = methodJson(m, usable, usable ? std::string() : est.ls.summary.message, est.beta, scoreOn(v, Wv, est.beta, truth));
      mj["std_error"] = toVector(est.std_error);
      j["methods"].push_back(mj);
      continue;
    }
    ident::Estimate e;
    try {
      e = otherEstimate(m, loaded.robot, d, rec, band, fit_signals, mo);
    } catch (const std::exception& ex) {
      // A method that cannot run on this record (e.g. without what IDIM-IV needs) fails alone:
      // the other methods' results stand.
      j["methods"].push_back(methodJson(m, false, ex.what(), Eigen::VectorXd(), {}));
      continue;
    }
    const bool usable = ident::usable(e.summary.status);
    j["methods"].push_back(methodJson(m, usable, usable ? std::string() : e.summary.message, e.x, scoreOn(v, Wv, e.x, truth)));
  }
  return j;
}

SweepConfig withChainDesign(SweepConfig config, const std::string& dir, std::ostream& log) {
  const bool optimised = std::count(config.trajectories.begin(), config.trajectories.end(), "optimised") > 0;
  if (!config.isChain() || !optimised || config.chain_design) return config;
  // A folder this sweep already started keeps its design: a resume, a rerun or another shard
  // never designs again (an optimisation's last bits may differ on another machine).
  const std::string cfg = dir + "/config.json";
  if (std::filesystem::exists(cfg)) {
    const nlohmann::json old = readJsonFile(cfg);
    if (old.contains("simulation") && old["simulation"].contains("excitation")) {
      try {
        config.chain_design = sim::trajectoryFromJson(old["simulation"]["excitation"]);
      } catch (const std::exception& e) {
        throw std::invalid_argument(cfg + ": its simulation.excitation is not a chain design (" + e.what() + ")");
      }
      log << "exoid sweep: the optimised record's design from " << cfg << "\n";
      return config;
    }
  }
  log << "exoid sweep: designing the optimised record (exoid excite --model " << config.model << ", seed of master_seed "
      << config.master_seed << "; give [simulation] excitation to reuse a design)\n";
  ExciteRequest ex;
  ex.model = config.chain_model_path;
  ex.selection = config.chain_selection;
  ex.out = dir + "/design.json";
  ex.options.seed = core::deriveSeed(config.master_seed, 0);
  ex.plot = false;
  excite(ex);
  config.chain_design = readExcitationFile(ex.out);
  return config;
}

}  // namespace exoid::experiments
