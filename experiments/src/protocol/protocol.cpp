#include "exoid/experiments/protocol/protocol.hpp"

#include "exoid/core/format.hpp"
#include "exoid/experiments/protocol/controller_io.hpp"
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/experiments/protocol/sim_bridge.hpp"
#include "exoid/ident/signals/band.hpp"
#include "exoid/ident/estimators/noise_covariance.hpp"
#include "exoid/core/random.hpp"
#include "exoid/ident/estimators/segmental.hpp"
#include "exoid/ident/estimators/stopwatch.hpp"

#include <stdexcept>

namespace exoid::experiments {

const char* toString(Variant v) {
  switch (v) {
    case Variant::kLs: return "ls";
    case Variant::kRls: return "rls";
    case Variant::kPso: return "pso";
    case Variant::kRlsPso: return "rls-pso";
    case Variant::kLad: return "lad";
    case Variant::kLsExact: return "ls-exact";
    case Variant::kLsStacked: return "ls-stacked";
    case Variant::kLsParallel: return "ls-parallel";
    case Variant::kIdimIv: return "idim-iv";
    case Variant::kLsBase: return "ls-base";
    case Variant::kIdimIvBase: return "idim-iv-base";
    case Variant::kDefault: return "default";
  }
  return "unknown";
}

const std::vector<Variant>& allVariants() {
  static const std::vector<Variant> all = {Variant::kLs,  Variant::kRls,     Variant::kPso,      Variant::kRlsPso,
                                           Variant::kLad, Variant::kLsExact, Variant::kLsStacked,
                                           Variant::kLsParallel, Variant::kIdimIv, Variant::kLsBase, Variant::kIdimIvBase,
                                           Variant::kDefault};
  return all;
}

Variant parseVariant(const std::string& name) {
  for (Variant v : allVariants()) {
    if (name == toString(v)) return v;
  }
  throw std::invalid_argument("unknown method '" + name + "' (expected ls, rls, pso, rls-pso, lad, ls-exact, ls-stacked, ls-parallel, idim-iv, ls-base, idim-iv-base or default)");
}

void ProtocolConfig::validate() const {
  sim.validate();
  if (signals.cutoff_from_data || signals.derivative_cutoff_from_data) {
    throw std::invalid_argument("the protocol's arms use fixed cutoffs (its 'default' arm chooses its own band per record): "
                                "give --cutoff-hz and --derivative-cutoff-hz as numbers, not auto");
  }
  signals.validateFor(1.0 / sim.dt_s);  // the records' rate: a cutoff above its Nyquist fails every run
  if (signals.processing != ident::Processing::kPaper) {
    throw std::invalid_argument("the protocol's arms use the paper's signal processing ('--processing paper'); "
                                "a parallel-processing arm is not part of it yet");
  }
  methods.validate();
  iv.validate();
  band_rule.validate();
  if (knee_excitation) {
    knee_excitation->validate();
    if (!knee_excitation->locked_joints) throw std::invalid_argument("the knee excitation must hold the hip (design it with exoid excite --knee-only)");
  }
  if (both_excitation) {
    both_excitation->validate();
    if (both_excitation->locked_joints) throw std::invalid_argument("the both-joint excitation must move the hip (design it without --knee-only)");
  }
  if (variants.empty()) throw std::invalid_argument("'methods' must name at least one method");
}

ident::SignalOptions parallelSignals(const ident::SignalOptions& paper, bool base_terms) {
  ident::SignalOptions o = paper;
  o.processing = ident::Processing::kParallel;
  o.base_terms = base_terms ? ident::BaseTerms::kOn : ident::BaseTerms::kOff;
  return o;
}

std::uint64_t recordSeed(std::uint64_t seed, int trajectory) {
  return core::deriveSeed(seed, static_cast<std::uint64_t>(trajectory));
}
std::uint64_t psoSeed(std::uint64_t seed) { return core::deriveSeed(seed, 100); }

namespace {

// Exact states and the `tau_suffix` torques, trimmed like the processed signals (same rows).
ident::JointSignals alignedExact(const ident::Dataset& d, const std::string& tau_suffix, const ident::SignalOptions& o) {
  return ident::trimEdges(exactSignals(d, tau_suffix), o.edgeTrimSamples(1.0 / d.sampleInterval_s()));
}

}  // namespace

std::array<Record, 4> simulateRecords(const ProtocolConfig& c) {
  std::array<Record, 4> out;
  for (int k = 0; k < 4; ++k) {
    Record& r = out[static_cast<std::size_t>(k)];
    r.trajectory = k + 1;
    sim::SimConfig sc = c.sim;
    sc.trajectory = k + 1;
    const std::optional<core::FourierSeries>& designed = k == 0 ? c.knee_excitation : k == 2 ? c.both_excitation : std::nullopt;
    if (designed) {
      sc.trajectory = 0;
      sc.fourier = *designed;
    }
    sc.seed = recordSeed(c.seed, k + 1);
    sc.exact_columns = true;
    r.sim = sim::simulate(sc);
    r.data = toDataset(r.sim);
    r.processed = ident::prepareSignals(r.data, c.signals);
    // Exact derivative columns with the raw measured torque: unfiltered, because the exact
    // acceleration keeps the high-frequency motion the filtered torque would lose.
    r.exact_q = alignedExact(r.data, "true", c.signals);
    const Eigen::Index trim = c.signals.edgeTrimSamples(1.0 / r.data.sampleInterval_s());
    r.exact_q.tau_Nm = r.data.tau_Nm.middleRows(trim, r.exact_q.size());
    r.ideal = alignedExact(r.data, "ideal", c.signals);
    r.robot = ident::twoLinkLeg(constantsOf(r.sim.truth));
    r.processed_rows = ident::recordRows(r.robot, r.processed);
    r.exact_rows = ident::recordRows(r.robot, r.exact_q);
    if (k != 0 && k != 2) continue;  // the parallel arms identify on records 1 and 3 only
    r.closed_loop.signals = parallelSignals(c.signals);
    r.closed_loop.measured = ident::processRecord(r.data, r.robot, r.closed_loop.signals);
    r.closed_loop.reference = referenceOf(r.data, "record " + core::toText(k + 1));
    r.closed_loop.controller = controllerOf(sc, k < 2);
    r.closed_loop_base = r.closed_loop;
    r.closed_loop_base.signals = parallelSignals(c.signals, true);
    r.closed_loop_base.measured = ident::processRecord(r.data, r.robot, r.closed_loop_base.signals);
    // Record 1's hip is held by the rig's lock: no hip torque is measured, its knee equation judges.
    ident::BandRule rule = c.band_rule;
    rule.first_moving_joint = k == 0 ? 1 : 0;
    r.default_signals = ident::resolveSignalOptions(r.data, r.robot, defaultArmSignals(c), rule);
    r.default_rows = ident::processRecord(r.data, r.robot, r.default_signals);
  }
  return out;
}

ident::SignalOptions defaultArmSignals(const ProtocolConfig& c) {
  ident::SignalOptions o = defaultIdentifySignals();
  if (c.default_base_terms) o.base_terms = *c.default_base_terms;
  return o;
}

Truths truthsOf(const std::array<Record, 4>& r, const ident::LegConstants& lc) {
  Truths t;
  t.rigid = toParamVector(r[0].sim.truth.x);
  t.lt_m = lc.thigh_length_m;
  t.g_mps2 = lc.gravity_mps2;
  ident::MethodOptions o;
  o.report_optimality_gap = false;
  const ident::Robot robot = ident::twoLinkLeg(lc);
  const ident::SegmentalResult bf =
      ident::identifySegmental(robot, {{1, ident::recordRows(robot, r[0].ideal)}, {0, ident::recordRows(robot, r[2].ideal)}}, ident::Method::kLs, o);
  t.best_fit = bf.theta.head<ident::kNumParams>();
  const ident::ParamVector lo1 = toParamVector(r[0].sim.lumped_band.min), hi1 = toParamVector(r[0].sim.lumped_band.max);
  const ident::ParamVector lo3 = toParamVector(r[2].sim.lumped_band.min), hi3 = toParamVector(r[2].sim.lumped_band.max);
  t.band_min << lo3.head<5>(), lo1.tail<5>();
  t.band_max << hi3.head<5>(), hi1.tail<5>();
  return t;
}

namespace {

MethodOutcome runVariant(Variant v, const std::array<Record, 4>& r, const ProtocolConfig& c, const ident::MethodOptions& o) {
  const ident::Robot& robot = r[0].robot;
  const auto segmented = [&](ident::Method m, const ident::RecordRows& knee, const ident::RecordRows& both) {
    return identifySegmented(robot, m, knee, both, o);
  };
  switch (v) {
    case Variant::kLsParallel: return segmented(ident::Method::kLs, r[0].closed_loop.measured, r[2].closed_loop.measured);
    case Variant::kIdimIv: return identifySegmentedIdimIv(robot, r[0].closed_loop, r[2].closed_loop, c.iv);
    case Variant::kLsBase: return segmented(ident::Method::kLs, r[0].closed_loop_base.measured, r[2].closed_loop_base.measured);
    case Variant::kIdimIvBase: return identifySegmentedIdimIv(robot, r[0].closed_loop_base, r[2].closed_loop_base, c.iv);
    case Variant::kDefault: {
      // identify --knee-data --both-data with no options: the segmental LS estimate, moved to the
      // nearest physically consistent one in its reported errors' metric.
      MethodOutcome m = segmented(ident::Method::kLs, r[0].default_rows, r[2].default_rows);
      if (m.segmental_errors) applySegmentalConsistency(m, *robot.two_link, ident::ConsistencyOptions{});
      return m;
    }
    case Variant::kLs: return segmented(ident::Method::kLs, r[0].processed_rows, r[2].processed_rows);
    case Variant::kRls: return segmented(ident::Method::kRls, r[0].processed_rows, r[2].processed_rows);
    case Variant::kPso: return segmented(ident::Method::kPso, r[0].processed_rows, r[2].processed_rows);
    case Variant::kRlsPso: return segmented(ident::Method::kRlsPso, r[0].processed_rows, r[2].processed_rows);
    case Variant::kLad: return segmented(ident::Method::kLad, r[0].processed_rows, r[2].processed_rows);
    case Variant::kLsExact: return segmented(ident::Method::kLs, r[0].exact_rows, r[2].exact_rows);
    case Variant::kLsStacked: {
      // Record 1's hip is held by the rig's lock, not its motor: no hip torque is measured there,
      // so only its knee equation enters; record 3 gives both equations.
      const Eigen::MatrixXd H1 = r[0].processed_rows.jointW(1);
      const Eigen::MatrixXd& H3 = r[2].processed_rows.W;
      Eigen::MatrixXd H(H1.rows() + H3.rows(), ident::kNumParams);
      H << H1, H3;
      Eigen::VectorXd y(H.rows());
      y << r[0].processed_rows.jointY(1), r[2].processed_rows.y;
      MethodOutcome m;
      m.method = ident::Method::kLs;
      Stage st{"stacked", {0, 1, 2, 3, 4, 5, 6, 7, 8, 9}, ident::estimate(ident::Method::kLs, H, y, o)};
      m.x = st.estimate.x;
      m.stages.push_back(std::move(st));
      return m;
    }
  }
  throw std::logic_error("unhandled variant");
}

}  // namespace

Eigen::VectorXd noiseStd(Variant v, const std::array<Record, 4>& r, const ident::SignalOptions& signals, double sigma_Nm) {
  const bool exact = v == Variant::kLsExact;
  const bool base = v == Variant::kLsBase || v == Variant::kIdimIvBase;
  const bool byDefault = v == Variant::kDefault;
  const bool parallel = v == Variant::kLsParallel || v == Variant::kIdimIv || base || byDefault;
  const ident::SignalOptions path_signals = parallel ? parallelSignals(signals, base) : signals;
  // The torque noise path of record k: the variant's processing of a raw record of its length.
  const auto path = [&](int k) {
    const ident::Dataset& d = r[static_cast<std::size_t>(k)].data;
    const double fs = 1.0 / d.sampleInterval_s();
    if (byDefault) return ident::torqueNoisePath(r[static_cast<std::size_t>(k)].default_signals, fs, d.size());
    return exact ? ident::rawTorquePath(d.size(), signals.edgeTrimSamples(fs))
                 : ident::torqueNoisePath(path_signals, fs, d.size());
  };
  // The fitted rows: the parallel arms fit the filtered, decimated columns themselves.
  const auto rows = [&](int k, ident::Joint joint) -> Eigen::MatrixXd {
    const Record& rec = r[static_cast<std::size_t>(k)];
    const ident::RecordRows& p = !parallel ? (exact ? rec.exact_rows : rec.processed_rows)
                                 : byDefault ? rec.default_rows
                                 : base      ? rec.closed_loop_base.measured
                                             : rec.closed_loop.measured;
    return p.jointW(static_cast<Eigen::Index>(joint));
  };
  const Eigen::MatrixXd K1 = rows(0, ident::Joint::kKnee);
  const Eigen::MatrixXd H3 = rows(2, ident::Joint::kHip);
  if (v == Variant::kLsStacked) {
    const Eigen::MatrixXd K3 = rows(2, ident::Joint::kKnee);
    return ident::stdOf(ident::lsNoiseCovariance({{K1, path(0), sigma_Nm}, {H3, path(2), sigma_Nm}, {K3, path(2), sigma_Nm}}));
  }
  const ident::NoiseChannel knee{K1.middleCols(ident::kShankFirst, ident::kGroupSize), path(0), sigma_Nm};
  const ident::NoiseChannel hip{H3.middleCols(ident::kThighFirst, ident::kGroupSize), path(2), sigma_Nm};
  return ident::stdOf(ident::segmentalNoiseCovariance(knee, hip, H3.middleCols(ident::kShankFirst, ident::kGroupSize)));
}

ProtocolResult runProtocol(const ProtocolConfig& c) {
  c.validate();
  ident::Stopwatch clock;
  ProtocolResult res;
  res.config = c;
  res.records = simulateRecords(c);
  const ident::LegConstants lc = constantsOf(res.records[0].sim.truth);
  res.truths = truthsOf(res.records, lc);
  ident::MethodOptions o = c.methods;
  o.rls_pso.pso.seed = psoSeed(c.seed);
  for (Variant v : c.variants) {
    VariantScore s;
    s.variant = v;
    s.outcome = runVariant(v, res.records, c, o);
    const Eigen::MatrixX2d knee_pred = ident::predictTorque(res.records[1].processed, s.outcome.x, lc);
    const Eigen::MatrixX2d hip_pred = ident::predictTorque(res.records[3].processed, s.outcome.x, lc);
    s.knee_validation = ident::torqueError(res.records[1].processed.tau_Nm.col(1), knee_pred.col(1));
    s.hip_validation = ident::torqueError(res.records[3].processed.tau_Nm.col(0), hip_pred.col(0));
    s.vs_rigid = ident::paramError(s.outcome.x, res.truths.rigid);
    s.vs_best_fit = ident::paramError(s.outcome.x, res.truths.best_fit);
    s.torque_space_vs_rigid = ident::torqueSpaceError(s.outcome.x, res.truths.rigid, lc);
    s.torque_space_vs_best_fit = ident::torqueSpaceError(s.outcome.x, res.truths.best_fit, lc);
    s.crb_std = noiseStd(v, res.records, c.signals, c.sim.sensors.noise_tau_Nm);
    res.scores.push_back(std::move(s));
  }
  res.wall_time_s = clock.seconds();
  return res;
}

}  // namespace exoid::experiments
