// `exoid simulate` and `exoid identify` on a chain model (not the APAL leg).
#include "exoid/experiments/commands/robot_commands.hpp"

#include "exoid/core/atomic_file.hpp"
#include "exoid/core/format.hpp"
#include "exoid/core/normal_tail.hpp"
#include "exoid/experiments/commands/commands.hpp"
#include "exoid/experiments/protocol/controller_io.hpp"
#include "exoid/experiments/protocol/excitation_report.hpp"
#include "exoid/experiments/protocol/fit_records.hpp"
#include "exoid/experiments/protocol/band_sensitivity.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/protocol/identify_report.hpp"
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/experiments/protocol/robot_loader.hpp"
#include "exoid/experiments/report/plots.hpp"
#include "exoid/experiments/report/table.hpp"
#include "exoid/ident/estimators/band_iv.hpp"
#include "exoid/ident/estimators/idim_iv.hpp"
#include "exoid/ident/estimators/stopwatch.hpp"
#include "exoid/ident/model/base_estimate.hpp"
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/ident/signals/processing.hpp"
#include "exoid/sim/model.hpp"
#include "exoid/sim/serial_chain.hpp"
#include "exoid/sim/sidecar.hpp"
#include "exoid/sim/trajectory_json.hpp"

#include <Eigen/Cholesky>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <iostream>
#include <map>
#include <sstream>

namespace exoid::experiments {

namespace {

nlohmann::json namedValues(const std::vector<std::string>& names, const Eigen::VectorXd& v) {
  nlohmann::json j = nlohmann::json::object();
  for (std::size_t i = 0; i < names.size(); ++i) j[names[i]] = v[static_cast<Eigen::Index>(i)];
  return j;
}

nlohmann::json namedStrings(const std::vector<std::string>& names, const std::vector<std::string>& values) {
  nlohmann::json j = nlohmann::json::object();
  for (std::size_t i = 0; i < names.size() && i < values.size(); ++i) j[names[i]] = values[i];
  return j;
}

}  // namespace

std::vector<double> toVector(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

nlohmann::json baseErrorsJson(const Eigen::VectorXd& reported, const ident::ReportedErrors& e, const char* are) {
  return {{"std_error", toVector(reported)},
          {"std_error_newey_west", toVector(e.newey_west)},
          {"std_error_jackknife", toVector(e.jackknife)},
          {"std_error_record_jackknife", toVector(e.record_jackknife)},
          {"std_error_are", are}};
}

sim::ChainSimConfig chainSimConfig(const sim::SimConfig& s) {
  sim::ChainSimConfig c;
  c.model_path = s.model_path;
  c.duration_s = s.duration_s;
  c.dt_s = s.dt_s;
  c.sensors = s.sensors;
  c.sensors.tau_bandwidth_Hz = 0.0;  // the chain rig's torque sensor: ideal unless --torque-sensor-bandwidth
  c.sensors.tau_bias_Nm.clear();     // the APAL leg's hip and knee biases
  c.vibration_level = s.variant.vibration_level;
  c.feedforward = s.feedforward;
  c.seed = s.seed;
  return c;
}

ident::Dataset chainDataset(const sim::ChainSimResult& r) {
  ident::CsvReadOptions o;
  o.joints = r.chain.jointNames();
  return ident::parseDatasetText(sim::tableCsv(r.table), r.chain.name + " simulation", o);
}

nlohmann::json chainSimulationSidecar(const sim::ChainSimResult& r) {
  const ident::ChainModel model = chainModel(r.chain);
  const Eigen::VectorXd phi = standardParameters(r.chain);
  const ident::BaseParameters base = ident::baseParameters(model);
  const sim::ChainSimConfig& c = r.config;
  nlohmann::json j;
  j["tool"] = toolJson();
  j["mujoco_version"] = r.mujoco_version;
  j["model"] = {{"name", r.chain.name}, {"path", c.model_path}, {"joints", model.jointNames()}};
  j["model"]["selection"] = c.selection.label();  // which chain of the file (identify --truth checks it)
  j["config"] = {{"duration_s", c.duration_s},
                 {"dt_s", c.dt_s},
                 {"seed", c.seed},
                 {"encoder_noise_deg", c.sensors.noise_q_deg},
                 {"quantisation_deg", c.sensors.quantisation_deg},
                 {"encoder_backlash_deg", c.sensors.encoder_backlash_deg},
                 {"torque_noise_Nm", c.sensors.noise_tau_Nm},
                 {"torque_bias_Nm", c.sensors.tau_bias_Nm.empty() ? std::vector<double>(r.chain.links.size(), 0.0) : c.sensors.tau_bias_Nm},
                 {"torque_sensor_bandwidth_Hz", c.sensors.tau_bandwidth_Hz},
                 {"imu_acc_noise_mps2", c.sensors.imu_acc_noise_mps2},
                 {"imu_gyro_noise_radps", c.sensors.imu_gyro_noise_radps},
                 {"vibration_level", c.vibration_level},
                 {"coulomb_v0_radps", c.coulomb_v0_radps},
                 {"bandwidth_hz", c.bandwidth_hz},
                 {"integral_hz", c.integral_hz},
                 {"feedforward", c.feedforward},
                 {"actuator_bandwidth_hz", c.actuator_bandwidth_hz},
                 {"record_derivatives", c.record_derivatives},
                 {"locked", c.locked},
                 {"trajectory", sim::trajectoryJson(c.trajectory, model.jointNames())}};
  j["tracking_rms_rad"] = r.tracking_rms_rad;
  // The rig's controller in the form `identify --controller` reads (N m/rad, N m s/rad, Hz; also
  // the CSV's controller_* metadata lines): u = ff(ref) + kp (q_ref - q_read) [+ ki int(q_ref - q_read)] + kd (qd_ref - qd).
  j["controller"] = {{"kp", toVector(r.kp_Nm_per_rad)},
                     {"kd", toVector(r.kd_Nms_per_rad)},
                     {"derivative", "measured_velocity"},
                     {"feedforward", c.feedforward ? "model" : "none"},
                     {"actuator_bandwidth_hz", c.actuator_bandwidth_hz}};
  if (c.integral_hz > 0.0) {
    j["controller"]["ki"] = toVector(r.ki_Nm_per_rad_s);
    j["controller"]["integral_limit_Nm"] = c.integral_limit_Nm;
  }
  j["truth"] = {{"standard_parameters", namedValues(model.standardParameterNames(), phi)},
                {"base_parameters", namedValues(base.names, base.combination * phi)},
                {"coulomb", (c.coulomb_v0_radps > 0.0 ? "fc tanh(qd / v0)" : "fc sgn(qd)")},
                {"description", "Rigid links lumped per joint (every body welded below it), the model's damping as fv and armature as Ia; "
                                "base parameters: QR with column pivoting over random states (exoid identifiability --model)"}};
  return j;
}

void truthOfChain(const std::string& model_path, const std::string& json_out, const core::ChainSelection& selection) {
  core::prepareOutputFile(json_out);
  const LoadedChain loaded = loadChain(model_path, {}, selection);
  const auto& [path, chain_selection, chain, model, phi, base, robot] = loaded;
  std::cout << "Standard parameters of " << chain.name << " (" << model_path << "), each link's about its joint, in its frame:\n";
  TextTable table({"parameter", "value"});
  const std::vector<std::string> names = model.standardParameterNames();
  for (std::size_t i = 0; i < names.size(); ++i) table.addRow({names[i], fmt(phi[static_cast<Eigen::Index>(i)], 8)});
  table.print(std::cout);
  std::cout << "Base parameters (" << base.rank << "):\n";
  TextTable bt({"base parameter", "value"});
  const Eigen::VectorXd beta = base.combination * phi;
  for (int i = 0; i < base.rank; ++i) bt.addRow({base.names[static_cast<std::size_t>(i)], fmt(beta[i], 8)});
  bt.print(std::cout);
  printCombinations(std::cout, base.names, base.combinations);
  if (!json_out.empty()) {
    writeJsonFile(json_out, {{"tool", toolJson()},
                             {"model", {{"name", chain.name}, {"path", model_path}, {"joints", model.jointNames()}, {"selection", chain_selection.label()}}},
                             {"truth", {{"standard_parameters", namedValues(names, phi)}, {"base_parameters", namedValues(base.names, beta)}}},
                             {"base_parameter_combinations", namedStrings(base.names, base.combinations)}});
  }
}

void simulateChainToFiles(const sim::ChainSimConfig& config, const std::string& csv_path) {
  const std::string json_path = sim::sidecarPathOf(csv_path);
  core::prepareOutputFile(csv_path);
  core::prepareOutputFile(json_path);
  const sim::ChainSimResult r = sim::simulateChain(config);
  const nlohmann::json side = chainSimulationSidecar(r);
  sim::writeTableCsv(r.table, csv_path);
  writeJsonFile(json_path, side);
  std::cout << "wrote " << csv_path << " (" << r.table.rows() << " samples of " << r.chain.name << ": ";
  for (std::size_t i = 0; i < r.chain.links.size(); ++i) std::cout << (i ? ", " : "") << r.chain.links[i].joint;
  std::cout << ") and " << json_path << "\ntracking error RMS " << fmt(r.tracking_rms_rad * 180.0 / M_PI, 3) << " deg (all joints)\n";
}

namespace {

// The verdict when the draws cannot be made (judgeConsistency refused the covariance): the distance
// judged as if one bound were active, as before the draws, and said so.
ident::ConsistencyVerdict verdictOrDistance(const std::function<ident::ConsistencyVerdict()>& judge, const ident::ConsistentFit& fit,
                                            const Eigen::VectorXd& theta, const Eigen::MatrixXd& covariance, double significance_sigmas,
                                            const std::string& whose) {
  try {
    return judge();
  } catch (const std::invalid_argument& e) {
    ident::ConsistencyVerdict v;
    if (fit.status != ident::ConsistentFitStatus::kLeastSquaresConsistent) {
      const Eigen::VectorXd d = fit.beta - theta;
      v.distance = std::sqrt(std::max(0.0, d.dot(covariance.ldlt().solve(d))));
    }
    v.level = core::normalUpperTail(significance_sigmas);
    v.p_value = v.distance > 0.0 ? core::normalUpperTail(v.distance) : 1.0;
    v.significant = v.distance > significance_sigmas;
    std::cout << wrapped(whose + "'s physical consistency: not judged by draws (" + std::string(e.what()) + "): its distance " +
                         fmt(v.distance, 3) + " against --significance alone")
              << "\n";
    return v;
  }
}

}  // namespace

std::optional<NearestConsistent> nearestConsistent(const LoadedChain& loaded, const Eigen::VectorXd& theta, const Eigen::MatrixXd& covariance,
                                                  const std::string& whose, const ident::ConsistencyVerdictOptions& options) {
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(covariance);
  if (!covariance.allFinite() || ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0.0).all()) return std::nullopt;
  const Eigen::MatrixXd A = ldlt.solve(Eigen::MatrixXd::Identity(theta.size(), theta.size()));
  NearestConsistent c;
  try {
    c.fit = ident::consistentFitNormal(loaded.model, loaded.base, A, A * theta, theta.dot(A * theta), loaded.phi, options.fit);
  } catch (const std::invalid_argument& e) {
    std::cout << wrapped(whose + "'s physical consistency: not judged (" + std::string(e.what()) + ")") << "\n";
    return std::nullopt;
  }
  c.verdict = verdictOrDistance([&] { return ident::judgeConsistency(loaded.model, loaded.base, theta, c.fit, A, covariance, loaded.phi, options); },
                                c.fit, theta, covariance, options.significance_sigmas, whose);
  return c;
}

void judgeOthersConsistency(const ChainIdentifyArgs& a, const LoadedChain& loaded, const Eigen::MatrixXd& covariance, ChainFit& fit) {
  for (const auto& [m, x] : fit.others) {
    if (!x.allFinite()) continue;  // an unusable estimate is named as such already
    const std::optional<NearestConsistent> c = nearestConsistent(loaded, x, covariance, m, verdictOptions(a));
    if (!c) continue;
    fit.json["methods"][m]["consistent"] = {{"consistent", c->fit.status == ident::ConsistentFitStatus::kLeastSquaresConsistent},
                                            {"ls_standard_errors_from_estimate", c->verdict.distance},
                                            {"verdict", toJson(c->verdict, a.consistency_seed)}};
    if (c->verdict.significant) fit.problems.push_back(m + ": " + inconsistencyProblem(c->verdict, "its estimate", "of LS's standard errors"));
  }
}

ident::ConsistencyVerdictOptions verdictOptions(const ChainIdentifyArgs& a) {
  ident::ConsistencyVerdictOptions o;
  o.significance_sigmas = a.significance_sigmas;
  o.draws = a.consistency_draws;
  o.seed = a.consistency_seed;
  o.threads = a.signals.threads;
  return o;
}

ident::ConsistencyVerdict consistencyVerdict(const LoadedChain& loaded, const ident::ChainEstimate& est, const ident::ConsistencyVerdictOptions& options) {
  if (!est.consistent) return {};
  return verdictOrDistance(
      [&] { return ident::judgeConsistency(loaded.model, loaded.base, est.beta, *est.consistent, est.normal, est.covariance, loaded.phi, options); },
      *est.consistent, est.beta, est.covariance, options.significance_sigmas, "LS");
}

std::string verdictText(const ident::ConsistencyVerdict& v) {
  if (v.draws == 0 && v.significant) return "judged by the distance against --significance alone (the draws could not be made)";
  if (v.draws == 0) return "p >= " + fmt(v.p_value, 3) + " (the half-normal bound, not drawn)";
  return core::toText(v.as_far) + " of " + core::toText(v.draws) + " estimates drawn about a consistent body lie as far (p = " + fmt(v.p_value, 3) + ")";
}

std::string inconsistencyProblem(const ident::ConsistencyVerdict& v, const std::string& whose, const char* errors) {
  return "no physically consistent body explains " + whose + ": the nearest consistent estimate is " + fmt(v.distance, 3) + " " + errors + " away; " +
         verdictText(v) + (v.draws > 0 ? ", at most " + fmt(v.level, 3) + " (--significance)" : std::string());
}

nlohmann::json toJson(const ident::ConsistencyVerdict& v, std::uint64_t seed) {
  return {{"standard_errors", v.distance}, {"p_value", v.p_value}, {"draws", v.draws}, {"as_far", v.as_far},
          {"level", v.level}, {"significant", v.significant}, {"seed", seed}};
}

namespace {

// The fit records, each processed in its own band (unless the flags fix it).
struct ChainFitRecords : FitRecords {
  std::vector<ident::BandIvRows> iv_rows;           ///< iv-band's rows and instruments, record by record
  std::vector<ident::ClosedLoopRecord> closed_loop;  ///< IDIM-IV's records: rows, reference, controller
};

ChainFitRecords readFitRecords(const ChainIdentifyArgs& a, const LoadedChain& loaded, const std::vector<ident::Dataset>& data) {
  const bool band_iv = std::find(a.methods.begin(), a.methods.end(), ident::Method::kIvBand) != a.methods.end();
  const bool idim_iv = std::find(a.methods.begin(), a.methods.end(), ident::Method::kIdimIv) != a.methods.end();
  ChainFitRecords fit{processFitRecords(a.data, data, loaded.robot, a.signals), {}, {}};
  for (std::size_t r = 0; r < data.size(); ++r) {
    const ident::Dataset& d = data[r];
    const std::optional<ident::BandChoice>& band = fit.bands[r];
    const ident::SignalOptions& used = fit.signals[r];
    if (band_iv) {
      // Instruments from the angles low-passed at the motion's bandwidth, in the record's own band.
      const double fm = band ? band->motion_bandwidth_hz : ident::motionBandwidth(d);
      fit.iv_rows.push_back(ident::bandIvRows(d, loaded.robot, used, fm));
    }
    if (idim_iv) {
      if (const auto locked = d.metadata("locked_joints"); locked && !locked->empty()) {
        throw std::invalid_argument(a.data[r] + ": joints " + *locked + " are locked in this record (metadata 'locked_joints'); IDIM-IV "
                                    "fits every joint's equation of --data: give it records in which every joint moves");
      }
      fit.closed_loop.push_back(closedLoopRecord(d, a.data[r], fit.rows[r], used, a.controller));
    }
  }
  return fit;
}

using MethodEstimates = std::vector<std::pair<ident::Method, ident::Estimate>>;

// The other methods' options: the PSO box from the data (10 x the largest |LS estimate|) unless given.
ident::MethodOptions chainMethodOptions(const ChainIdentifyArgs& a, const ident::ChainEstimate& est) {
  ident::MethodOptions mo = a.method_options;
  mo.ls.max_condition = a.max_condition;
  if (!a.wide_box_given) mo.wide_box_half_width = ident::psoHalfWidthFromLs(est.beta);
  return mo;
}

// The paper's methods over the same rows, in base parameters (LS, the reference, is not among them).
MethodEstimates otherMethods(const ChainIdentifyArgs& a, const LoadedChain& loaded, const ident::RecordRows& stacked,
                             const ChainFitRecords& fit, const ident::MethodOptions& mo) {
  const Eigen::MatrixXd& Wb = stacked.W;
  MethodEstimates others;
  for (ident::Method m : a.methods) {
    if (m == ident::Method::kLs) continue;
    if (m == ident::Method::kIvBand) {
      others.emplace_back(m, ident::solveBandIv(fit.iv_rows, mo.ls));
      continue;
    }
    if (m == ident::Method::kIdimIv) {
      ident::IvOptions iv = a.iv;
      iv.ls = mo.ls;
      others.emplace_back(m, ident::identifyIdimIv(loaded.robot, fit.closed_loop, iv));
      continue;
    }
    others.emplace_back(m, ident::estimate(m, Wb, stacked.y, mo));
  }
  return others;
}

// Each joint's RMS torque error of theta on v, N m.
std::vector<double> jointRms(const ident::RecordRows& v, const Eigen::VectorXd& theta) {
  std::vector<double> rms;
  for (const ident::TorqueErrorStats& e : jointTorqueErrors(v, theta)) rms.push_back(e.rms);
  return rms;
}

// One validation record: the LS estimate's torque error per joint (printed), the model file's
// own (CAD) model's, every other method's RMS error per joint.
nlohmann::json validationJson(const std::string& file, const ident::RecordRows& v, const LoadedChain& loaded, const Eigen::VectorXd& ls,
                              const std::vector<NamedEstimate>& others, const Eigen::VectorXd& cad) {
  const ident::ChainModel& model = loaded.model;
  const std::vector<double> error = jointRms(v, ls), measured = jointRms(v, Eigen::VectorXd::Zero(ls.size()));
  nlohmann::json vj = {{"file", file}, {"joints", nlohmann::json::array()}};
  std::ostringstream line;
  line << "validation " << file << ": torque error RMS";
  for (int j = 0; j < model.dof(); ++j) {
    const double err = error[static_cast<std::size_t>(j)], meas = measured[static_cast<std::size_t>(j)];
    line << (j ? ", " : " ") << model.joints[static_cast<std::size_t>(j)].name << " " << fmt(err, 4) << " N m (" << fmt(100.0 * err / meas, 3)
              << " % of the measured)";
    vj["joints"].push_back({{"name", model.joints[static_cast<std::size_t>(j)].name}, {"rms_error_Nm", err}, {"rms_measured_Nm", meas}});
  }
  std::cout << wrapped(line.str()) << "\n";
  // The model file's own parameters (the CAD's) on the same record: how much the identification gained.
  const std::vector<double> cad_rms = jointRms(v, cad);
  std::ostringstream cad_line;
  cad_line << "validation " << file << ": the model file's own parameters (CAD): torque error RMS";
  for (int j = 0; j < model.dof(); ++j) {
    cad_line << (j ? ", " : " ") << model.joints[static_cast<std::size_t>(j)].name << " " << fmt(cad_rms[static_cast<std::size_t>(j)], 4) << " N m";
    vj["joints"][static_cast<std::size_t>(j)]["cad_rms_error_Nm"] = cad_rms[static_cast<std::size_t>(j)];
  }
  std::cout << wrapped(cad_line.str()) << "\n";
  // Every other method's estimate on the same record: RMS torque error per joint, N m.
  for (const auto& [m, x] : others) vj["methods_rms_error_Nm"][m] = jointRms(v, x);
  return vj;
}

// Every --validate record, processed as the fit's first record (`fit_signals`): LS's and the
// model file's (CAD `cad`) torque error RMS per joint, printed, and every other method's.
struct ChainValidation {
  nlohmann::json json = nlohmann::json::array();
  std::optional<ident::RecordRows> first;  ///< the first validation record (what --plot shows)
};

ChainValidation validateChain(const ChainIdentifyArgs& a, const LoadedChain& loaded, const LogInput& log, const ident::SignalOptions& fit_signals,
                              const Eigen::VectorXd& ls, const std::vector<NamedEstimate>& others, const Eigen::VectorXd& cad) {
  ChainValidation out;
  for (const std::string& file : a.validate) {
    ident::RecordRows v = ident::processRecord(readLog(file, log), loaded.robot, fit_signals);
    out.json.push_back(validationJson(file, v, loaded, ls, others, cad));
    if (!out.first) out.first = std::move(v);
  }
  return out;
}

// --plot: the measured and LS-predicted torques of `shown`, and their series beside the figure.
void plotChainFit(const ChainIdentifyArgs& a, const LoadedChain& loaded, const Eigen::VectorXd& ls, const ident::RecordRows& shown) {
  plotTorqueFit(a.plot, loaded.model.jointNames(), shown, ls,
                loaded.chain.name + ": " + (a.validate.empty() ? "fit record " + a.data.front() : "validation record " + a.validate.front()));
}

// (ls - CAD) / standard error per base parameter; null where the standard error is not positive.
nlohmann::json cadDistances(const Eigen::VectorXd& ls, const Eigen::VectorXd& std_error, const Eigen::VectorXd& cad) {
  nlohmann::json out = nlohmann::json::array();
  for (Eigen::Index i = 0; i < cad.size(); ++i) out.push_back(std_error[i] > 0.0 ? nlohmann::json((ls[i] - cad[i]) / std_error[i]) : nlohmann::json());
  return out;
}

// Why the result must not be used (none: usable), and how far the consistent estimate is from LS.
struct ChainVerdict {
  std::vector<std::string> problems;
  ident::ConsistencyVerdict consistency;  ///< LS against its consistent estimate (distance 0 when LS is consistent)
};

// LS of full rank and not ill-conditioned: what its consistency and errors are judged on.
bool usableLs(const ident::BaseParameters& base, const ident::ChainEstimate& est) {
  return est.ls.rank == base.rank && est.ls.summary.status != ident::Status::kIllConditioned;
}

// Why the result must not be used, besides LS's consistency (judgeLeastSquares).
ChainVerdict verdictOf(const ident::BaseParameters& base, const ident::ChainEstimate& est, const MethodEstimates& others, const LsConsistency& consistency) {
  ChainVerdict v;
  v.consistency = consistency.verdict;
  const bool usable_ls = usableLs(base, est);
  if (est.ls.rank < base.rank) {
    v.problems.push_back("the records do not identify every base parameter (rank " + core::toText(est.ls.rank) + " of " +
                         core::toText(base.rank) + ")");
  }
  if (est.ls.rank == base.rank && !usable_ls) v.problems.push_back(est.ls.summary.message);
  if (!consistency.reason.empty()) v.problems.push_back(consistency.problem());
  for (const auto& [m, e] : others) {
    if (!ident::usable(e.summary.status)) v.problems.push_back(std::string(ident::toString(m)) + ": " + e.summary.message);
    for (Eigen::Index i : boxBoundIndices(e)) {
      v.problems.push_back(std::string(ident::toString(m)) + ": " + boxBoundMessage(base.names[static_cast<std::size_t>(i)], e, i));
    }
  }
  return v;
}

}  // namespace

ArmatureTest armatureTest(const ChainIdentifyArgs& a, const LoadedChain& loaded, const LogInput& log, const std::vector<std::string>& files,
                          const std::vector<ident::SignalOptions>& signals) {
  std::vector<std::string> missing;
  for (const ident::ChainJoint& j : loaded.model.joints) {
    if (!j.armature) missing.push_back(j.name);
  }
  if (missing.empty()) return {};
  const ident::ChainModel with = withArmature(loaded.model, missing);
  ident::BaseParameterOptions bo;
  bo.planar_base_motion = a.moving_base_parameters;
  const ident::Robot robot = ident::chainRobot(with, bo);
  std::vector<ident::RecordRows> rows;
  for (std::size_t r = 0; r < files.size(); ++r) rows.push_back(ident::processRecord(readLog(files[r], log), robot, signals[r]));
  return armatureTest(robot, rows, missing, a.significance_sigmas, a.max_condition);
}

std::string LsConsistency::problem() const {
  if (hint.empty() || reason.empty()) return reason;
  return verdict.significant ? reason + "; " + hint : hint + " (" + reason + ")";
}

LsConsistency judgeLeastSquares(const ChainIdentifyArgs& a, const LoadedChain& loaded, const LogInput& log, const ident::ChainEstimate& est,
                                const std::vector<std::string>& files, const std::vector<ident::SignalOptions>& signals, const std::string& whose) {
  LsConsistency c;
  c.verdict = consistencyVerdict(loaded, est, verdictOptions(a));
  if (c.verdict.distance <= a.significance_sigmas) return c;
  c.armature = armatureTest(a, loaded, log, files, signals);
  c.hint = c.armature->hint();
  if (c.verdict.significant) {
    c.reason = inconsistencyProblem(c.verdict, whose, "standard errors");
  } else if (!c.hint.empty()) {
    // The armature leads (problem()); the distance is its context, not a reason of its own.
    c.reason = "the nearest physically consistent estimate to " + whose + " is " + fmt(c.verdict.distance, 3) + " standard errors away; " +
               verdictText(c.verdict) + ", more than " + fmt(c.verdict.level, 3) + " (--significance)";
  }
  return c;
}

namespace {

void printChainEstimates(const ident::BaseParameters& base, const ident::ChainEstimate& est, const MethodEstimates& others,
                         const std::optional<Eigen::VectorXd>& truth, const ident::ConsistencyVerdict& consistency, const Eigen::VectorXd& cad) {
  std::vector<std::string> header = {"base parameter", "ls", "std err"};
  if (est.consistent) header.push_back("consistent");
  for (const auto& [m, e] : others) header.push_back(ident::toString(m));
  header.insert(header.end(), {"CAD", "ls-CAD / se"});
  if (truth) header.insert(header.end(), {"truth", "ls err %", "err / std"});
  TextTable table(header);
  for (int i = 0; i < base.rank; ++i) {
    std::vector<std::string> row = {base.names[static_cast<std::size_t>(i)], fmt(est.beta[i], 6), fmt(est.std_error[i], 3)};
    if (est.consistent) row.push_back(fmt(est.consistent->beta[i], 6));
    for (const auto& [m, e] : others) row.push_back(fmt(e.x[i], 6));
    row.push_back(fmt(cad[i], 6));
    row.push_back(est.std_error[i] > 0.0 ? fmt((est.beta[i] - cad[i]) / est.std_error[i], 3) : "-");
    if (truth) {
      const double err = est.beta[i] - (*truth)[i];
      row.push_back(fmt((*truth)[i], 6));
      row.push_back(std::abs((*truth)[i]) > 0.0 ? fmt(100.0 * err / std::abs((*truth)[i]), 3) : "-");
      row.push_back(est.std_error[i] > 0.0 ? fmt(err / est.std_error[i], 3) : "-");
    }
    table.addRow(row);
  }
  table.print(std::cout);
  printCombinations(std::cout, base.names, base.combinations);
  std::cout << "CAD: the model file's own parameters; ls-CAD / se: their distance in standard errors\n";
  std::cout << "rows " << est.rows << ", condition number (columns scaled) " << fmt(est.ls.condition_number, 4) << ", residual RMS "
            << fmt(est.ls.residual_rms, 4) << " N m\n";
  if (est.consistent) {
    std::cout << wrapped("consistent estimate: " + est.consistent->message + " (" + fmt(consistency.distance, 3) + " standard errors from LS" +
                         (consistency.distance > 0.0 ? ", " + verdictText(consistency) : std::string()) + ")")
              << "\n";
  }
}

// The one fit's own JSON: its records, LS's errors, the consistent estimate, the other methods.
nlohmann::json oneFitJson(const LoadedChain& loaded, const nlohmann::json& processing_per_record, const ident::ChainEstimate& est,
                          const MethodEstimates& others, const ChainVerdict& verdict, bool with_history, std::uint64_t seed) {
  nlohmann::json j;
  j["processing_per_record"] = processing_per_record;
  j["base_parameters"] = {{"condition_number", est.ls.condition_number}, {"residual_rms_Nm", est.ls.residual_rms}, {"rows", est.rows}};
  j["base_parameters"].update(baseErrorsJson(est.std_error, est.errors, kReportedErrorsAre));
  if (est.consistent) {
    j["base_parameters"]["consistent"] = toVector(est.consistent->beta);
    j["consistent"] = {{"standard_parameters", namedValues(loaded.model.standardParameterNames(), est.consistent->phi)},
                       {"status", ident::toString(est.consistent->status)},
                       {"standard_errors_from_ls", verdict.consistency.distance},
                       {"verdict", toJson(verdict.consistency, seed)},
                       {"message", est.consistent->message}};
  }
  j["methods"] = nlohmann::json::object();
  for (const auto& [m, e] : others) {
    nlohmann::json& mj = j["methods"][ident::toString(m)] = estimateJson(e, with_history);
    mj["beta"] = toVector(e.x);
    if (e.box) mj["box"] = {{"lower", toVector(e.box->lower)}, {"upper", toVector(e.box->upper)}};
  }
  return j;
}

// One fit of every --data record together: LS with its errors and the consistent estimate, the
// determination, the excitation and band-sensitivity lines, the other methods over the same rows.
// `data` is released once read (a long log's memory).
ChainFit fitOnce(const ChainIdentifyArgs& a, const LoadedChain& loaded, const LogInput& log, std::vector<ident::Dataset>& data,
                 const std::optional<Eigen::VectorXd>& truth) {
  const ident::BaseParameters& base = loaded.base;
  const ChainFitRecords fit = readFitRecords(a, loaded, data);
  const ident::RecordRows stacked = ident::stackRecords(fit.rows);
  std::vector<int> every(static_cast<std::size_t>(base.rank));
  for (int i = 0; i < base.rank; ++i) every[static_cast<std::size_t>(i)] = i;
  const ident::Determination determination = ident::determination(loaded.robot, data, stacked, every);
  const std::string undetermined = undeterminedProblem(loaded.robot, determination);
  if (!undetermined.empty()) std::cout << undetermined << '\n';
  ident::ChainEstimateOptions eo;
  eo.ls.max_condition = a.max_condition;
  eo.consistent = a.consistency;
  // The band sensitivity's refit needs only the records: beside the estimate, on one core of its own
  // (the same bytes on any number of threads).
  std::vector<ident::SignalOptions> one_thread = fit.signals;
  for (ident::SignalOptions& o : one_thread) o.threads = 1;
  std::future<std::optional<BandRefit>> refit = std::async(std::launch::async, [&] {
    return refitInAWiderBand(data, one_thread, fit.bands, a.signals.derivative_cutoff_from_data, loaded.robot, stacked);
  });
  const ident::Stopwatch ls_time;
  const ident::ChainEstimate est = ident::estimateChain(loaded.robot, stacked, loaded.phi, eo);
  const double ls_time_s = ls_time.seconds();
  const std::optional<BandRefit> wider = refit.get();
  std::cout << wrapped(describe(excitationOf(est.ls, base.names), "the records",
                                "`exoid identifiability --model " + a.model + " --data FILE` says what motion would separate them; `exoid excite --model " +
                                    a.model + "` designs one"))
            << "\n";
  const std::optional<BandSensitivity> sensitivity =
      wider ? std::optional<BandSensitivity>(bandSensitivity(*wider, loaded.robot, est.beta, est.std_error)) : std::nullopt;
  data.clear();
  const ident::MethodOptions mo = chainMethodOptions(a, est);
  const MethodEstimates others = otherMethods(a, loaded, stacked, fit, mo);
  // A consistency failure an optional term explains says so, and names the option.
  const LsConsistency consistency = usableLs(base, est) ? judgeLeastSquares(a, loaded, log, est, a.data, fit.signals, "the data") : LsConsistency{};
  ChainVerdict verdict = verdictOf(base, est, others, consistency);
  if (!consistency.hint.empty()) std::cout << wrapped("implausible: " + consistency.hint) << "\n";
  const std::optional<ArmatureTest>& armature = consistency.armature;
  if (!undetermined.empty()) verdict.problems.insert(verdict.problems.begin(), undetermined);
  if (std::find(a.methods.begin(), a.methods.end(), ident::Method::kPso) != a.methods.end()) {
    std::cout << "PSO box (pso): +-" << fmt(mo.wide_box_half_width, 3) << " in every base parameter\n";
  }
  printChainEstimates(base, est, others, truth, verdict.consistency, base.combination * loaded.phi);
  if (sensitivity) {
    for (const std::string& line : describe(*sensitivity)) std::cout << wrapped(line) << "\n";
  }
  ChainFit out;
  out.ls = est.beta;
  out.std_error = est.std_error;
  for (const auto& [m, e] : others) out.others.emplace_back(ident::toString(m), e.x);
  out.method_options = mo;
  out.fit_signals = fit.validationSignals(a.signals);
  if (!a.plot.empty() && a.validate.empty()) out.shown = fit.rows.front();
  out.problems = verdict.problems;
  out.json = oneFitJson(loaded, fit.json, est, others, verdict, a.history, a.consistency_seed);
  out.json["base_parameters"]["wall_time_s"] = ls_time_s;  // LS with its errors and consistent estimate
  if (a.consistency) judgeOthersConsistency(a, loaded, est.covariance, out);
  out.json["determination"] = determinationJson(loaded.robot, determination, a.data);
  if (sensitivity) out.json["band_sensitivity"] = toJson(*sensitivity);
  if (armature) out.json["optional_terms"] = {{"armature", armature->json}, {"hint", armature->hint()}};
  return out;
}

}  // namespace

int identifyChain(const ChainIdentifyArgs& given) {
  ChainIdentifyArgs a = given;
  // A moving base's parameters are told apart by the base's motion alone: its terms are not judged.
  if (a.moving_base_parameters && a.signals.base_terms == ident::BaseTerms::kJudged) {
    a.signals.base_terms = ident::BaseTerms::kAuto;
    std::cout << "--base-terms judged: the base-motion terms are kept whenever a record has its IMU columns (a moving base's "
                 "parameters are told apart by its motion alone)\n";
  }
  if (a.data.empty()) {
    throw std::invalid_argument(a.stages.empty() ? "identify --model: give the records with --data (repeatable)"
                                                 : "--stage: the last stage, every joint moving, needs --data (repeatable)");
  }
  core::prepareOutputFile(a.json_out);
  core::prepareOutputFile(a.plot);
  const LoadedChain still = loadChain(a.model, a.armature, a.selection);
  LogInput log = resolveLogInput(a.log, a.signals.filter ? a.signals.cutoff_hz : 0.0, still.model.jointNames());
  log.check_record = recordOfChain(still);
  const std::vector<ChainStageInput> inputs = stageInputs(a, still.model);
  std::vector<std::vector<ident::Dataset>> data;
  nlohmann::json sampling = nlohmann::json::object();
  for (const ChainStageInput& in : inputs) {
    data.emplace_back();
    for (const std::string& file : in.files) {
      data.back().push_back(readLog(file, log));
      std::cout << "record " << file << ": " << samplingSummary(data.back().back(), log.csv) << '\n';
      sampling[file] = samplingJson(data.back().back());
    }
  }
  LoadedChain loaded = still;
  if (a.moving_base_parameters && data.size() == 1) {
    loaded = movingBase(still, data.front(), a.signals);  // one fit's records read in place (a long log is not copied)
  } else if (a.moving_base_parameters) {
    std::vector<ident::Dataset> all;
    for (const auto& stage : data) all.insert(all.end(), stage.begin(), stage.end());
    loaded = movingBase(still, all, a.signals);
  }
  const ident::BaseParameters& base = loaded.base;
  std::cout << "model " << loaded.chain.name << " (" << loaded.path << "): " << loaded.model.dof() << " joints, " << base.rank << " base parameters"
            << (a.stages.empty() ? "" : "; segmental strategy, distal joints first") << "\n";
  std::optional<Eigen::VectorXd> truth;
  if (!a.truth.empty()) truth = truthFromSidecar(a.truth, loaded);
  const ChainFit fit = a.stages.empty() ? fitOnce(a, loaded, log, data.front(), truth) : fitStages(a, loaded, log, inputs, data, truth);
  data.clear();

  // The validation records, the model file's own parameters (CAD) and --plot, whatever the strategy.
  const Eigen::VectorXd cad = base.combination * loaded.phi;
  const ChainValidation validation = validateChain(a, loaded, log, fit.fit_signals, fit.ls, fit.others, cad);
  if (!a.plot.empty()) plotChainFit(a, loaded, fit.ls, validation.first ? *validation.first : *fit.shown);
  if (!a.json_out.empty()) {
    nlohmann::json j = fit.json;
    IdentifyEnvelope envelope{{{"name", loaded.chain.name}, {"path", loaded.path}, {"joints", loaded.model.jointNames()}, {"left_out", loaded.chain.left_out}},
                              a.data, a.stages, a.validate, sampling, log.profile, a.signals, fit.method_options, fit.problems};
    j.update(toJson(envelope));
    nlohmann::json& b = j["base_parameters"];
    b["names"] = base.names;
    b["combinations"] = base.combinations;
    b["ls"] = toVector(fit.ls);
    b["cad"] = toVector(cad);
    b["cad_is"] = "the model file's own parameters (its CAD) in the same base parameters";
    if (fit.std_error) b["ls_minus_cad_std_errors"] = cadDistances(fit.ls, *fit.std_error, cad);
    if (truth) {
      b["truth"] = toVector(*truth);
      for (const auto& [m, x] : fit.others) {
        nlohmann::json& rel = j["methods"][m]["error_rel"] = nlohmann::json::array();  // null where the truth is 0
        for (Eigen::Index i = 0; i < x.size(); ++i) rel.push_back((*truth)[i] != 0.0 ? nlohmann::json((x[i] - (*truth)[i]) / std::abs((*truth)[i])) : nlohmann::json());
      }
    }
    j["validation"] = validation.json;
    writeJsonFile(a.json_out, a.timing ? j : withoutWallTimes(j));  // without: same input, same bytes
  }
  if (!fit.problems.empty()) {
    std::string all;
    for (const std::string& p : fit.problems) all += (all.empty() ? "" : "; ") + p;
    throw UnusableResult(all);
  }
  return 0;
}

}  // namespace exoid::experiments
