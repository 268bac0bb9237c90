#pragma once
// The commands on a robot model other than the APAL leg (any serial chain of revolute joints, from
// its MJCF or URDF): simulate it, identify its base parameters from logs.
#include "exoid/core/tree_selection.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/protocol/log_input.hpp"
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/estimators/idim_iv.hpp"
#include "exoid/ident/estimators/methods.hpp"
#include "exoid/ident/estimators/standard_errors.hpp"
#include "exoid/ident/model/base_estimate.hpp"
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/ident/model/consistency_verdict.hpp"
#include "exoid/ident/model/consistent_fit.hpp"
#include "exoid/ident/signals/preprocess.hpp"
#include "exoid/sim/motor_rig.hpp"
#include "exoid/sim/simulate.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace exoid::experiments {


/// The chain simulator's settings from `exoid simulate`'s (model, duration, dt, encoder noise and
/// resolution, torque noise, vibration, feedforward, seed); the chain-only ones keep their defaults.
sim::ChainSimConfig chainSimConfig(const sim::SimConfig& c);

/// A chain simulation's table as a dataset of the chain's joints.
ident::Dataset chainDataset(const sim::ChainSimResult& r);

/// `exoid simulate` on a chain model: writes the CSV and its sidecar (same name, .json: the
/// settings, seed, versions, and the truth: standard and base parameters).
void simulateChainToFiles(const sim::ChainSimConfig& config, const std::string& csv_path);

/// The sidecar of a chain simulation.
nlohmann::json chainSimulationSidecar(const sim::ChainSimResult& r);

/// `exoid truth --model` for a chain: its standard parameters (per link, about the joint) and base
/// parameters from the file; json_out (optional) gets {"truth": {"standard_parameters", "base_parameters"}},
/// the form identify --truth reads.
void truthOfChain(const std::string& model_path, const std::string& json_out, const core::ChainSelection& selection = {});

/// An Eigen vector as a std::vector (for JSON).
std::vector<double> toVector(const Eigen::VectorXd& v);
/// A fit's standard errors as a chain's identify JSON gives them beside base_parameters.ls:
/// std_error (`reported`, what the fit reports), _newey_west, _jackknife, _record_jackknife, _are.
nlohmann::json baseErrorsJson(const Eigen::VectorXd& reported, const ident::ReportedErrors& e, const char* are);

struct ChainIdentifyArgs {
  std::string model;                 ///< apal|leg3|FILE (.xml or .urdf)
  std::vector<std::string> data;     ///< records, fitted together (with stages: the last stage, every joint moving)
  /// The segmental strategy down the chain: (joint, record) pairs, the record's joints above
  /// `joint` locked (exoid simulate --lock); empty = one fit of --data.
  std::vector<std::pair<std::string, std::string>> stages;
  std::vector<std::string> validate;  ///< records the estimate predicts (torque error per joint)
  std::string plot;                  ///< PNG: measured and predicted torques of the first validation record (else the first fit record)
  std::string truth;                 ///< a chain simulation's sidecar: errors against its standard parameters' combinations
  /// Joints that get an armature (rotor inertia) parameter although the file gives none (a URDF
  /// never does), or {"all"}.
  std::vector<std::string> armature;
  core::ChainSelection selection;  ///< --base, --tip, --lock: the chain out of a tree
  /// Fit in the base parameters of a moving base (movingBase): records with base-motion terms.
  bool moving_base_parameters = false;
  std::string json_out;
  LogInputFlags log;
  ident::SignalOptions signals;
  bool consistency = true;
  double significance_sigmas = 2.0;
  int consistency_draws = 199;          ///< the consistency verdict's draws (ident::judgeConsistency)
  std::uint64_t consistency_seed = 1;   ///< and their seed
  double max_condition = 1e5;
  /// Besides LS (always): rls, pso, rls-pso, lad over the same base-parameter rows.
  std::vector<ident::Method> methods;
  ident::MethodOptions method_options;
  bool wide_box_given = false;  ///< else the PSO box is 10 x the largest |LS estimate|
  /// IDIM-IV: the rig's controller (JSON: kp, kd per joint, feedforward, actuator_bandwidth_hz);
  /// empty = each record's metadata (exoid simulate --model writes it). And its stopping rule.
  std::string controller;
  ident::IvOptions iv;
  bool timing = false;   ///< wall times in the JSON (they differ run to run)
  bool history = false;  ///< PSO's best-cost histories in the JSON
};
/// `exoid identify --model` for a chain: its base parameters by least squares, in one fit of
/// --data or down the chain's stages (--stage), their standard errors, the physically consistent
/// estimate, every other method's, the validation records; returns the exit code (0, or 3 naming
/// why the result must not be used).
int identifyChain(const ChainIdentifyArgs& args);

struct LoadedChain;
/// A method's estimate by its name (the methods other than LS), in the base parameters.
using NamedEstimate = std::pair<std::string, Eigen::VectorXd>;

/// The records of one stage of identify --model: those whose joints above `first_joint` are locked.
struct ChainStageInput {
  Eigen::Index first_joint = 0;
  std::vector<std::string> files;
};
/// The stages, distal first (--stage records grouped by their first moving joint), then --data's,
/// every joint moving: without --stage, --data's alone. Throws std::invalid_argument naming a
/// --stage whose joint is not the model's.
std::vector<ChainStageInput> stageInputs(const ChainIdentifyArgs& a, const ident::ChainModel& model);

/// What a strategy of identify --model (one fit, or the stages) leaves for the report they share:
/// the validation records, --plot, the CAD comparison, the JSON's common part and the exit code.
struct ChainFit {
  Eigen::VectorXd ls;                        ///< LS's base parameters
  /// LS's reported standard errors (one fit: NaN where LS cannot give one; stages: none when LS is unusable)
  std::optional<Eigen::VectorXd> std_error;
  std::vector<NamedEstimate> others;         ///< every other method's estimate
  ident::MethodOptions method_options;       ///< as the methods ran (the PSO box sized from the data)
  ident::SignalOptions fit_signals;          ///< the processing of the validation records: the last stage's first record's
  std::optional<ident::RecordRows> shown;    ///< that record's rows, kept only for --plot without --validate
  std::vector<std::string> problems;         ///< why the result must not be used (none: usable)
  nlohmann::json json;                       ///< the strategy's own JSON (records or stages, errors, consistency, methods)
};
/// The nearest physically consistent base parameters to `theta` in the metric of a covariance C,
/// min (b - theta)' C^-1 (b - theta), and the verdict on their distance from theta in those
/// standard errors (ident::judgeConsistency; 0 when theta is itself consistent); none when C is not
/// positive definite, or when the model's consistency cannot be judged (said on stdout, naming
/// `whose` estimate it is).
struct NearestConsistent {
  ident::ConsistentFit fit;
  ident::ConsistencyVerdict verdict;
};
std::optional<NearestConsistent> nearestConsistent(const LoadedChain& loaded, const Eigen::VectorXd& theta, const Eigen::MatrixXd& covariance,
                                                  const std::string& whose, const ident::ConsistencyVerdictOptions& options);
/// Every other method's estimate in `fit` judged as LS's is (the APAL leg's identify judges each
/// method's plausibility too): when no consistent body lies within --significance of LS's
/// standard errors (`covariance`) of it, a problem naming the method; in fit.json's
/// methods.<m>.consistent either way.
void judgeOthersConsistency(const ChainIdentifyArgs& a, const LoadedChain& loaded, const Eigen::MatrixXd& covariance, ChainFit& fit);

/// The segmental strategy down the chain: data[s] holds the records of stage inputs[s] (stageInputs),
/// every method fitted stage by stage (ident::identifySegmental), printed with `truth` when known.
ChainFit fitStages(const ChainIdentifyArgs& a, const LoadedChain& loaded, const LogInput& log, const std::vector<ChainStageInput>& inputs,
                   const std::vector<std::vector<ident::Dataset>>& data, const std::optional<Eigen::VectorXd>& truth);

/// The optional-term test (identification.hpp) of the records `files` (each processed as
/// `signals`): an armature on every joint the model gives none.
ArmatureTest armatureTest(const ChainIdentifyArgs& a, const LoadedChain& loaded, const LogInput& log, const std::vector<std::string>& files,
                          const std::vector<ident::SignalOptions>& signals);

/// The verdict on a chain's LS estimate against its physically consistent one (ident::judgeConsistency,
/// the distance in the fit's own covariance); distance 0 when LS is consistent or no consistent
/// estimate was computed. When the draws cannot be made (the covariance is not positive definite),
/// the distance against --significance alone, said on stdout (draws 0 beyond --significance).
ident::ConsistencyVerdict consistencyVerdict(const LoadedChain& loaded, const ident::ChainEstimate& est,
                                             const ident::ConsistencyVerdictOptions& options);
/// The verdict's options from identify's: --significance, --consistency-draws, --consistency-seed, --threads.
ident::ConsistencyVerdictOptions verdictOptions(const ChainIdentifyArgs& a);
/// LS's physical consistency as identify judges it (one fit, or the stages' one fit of the last
/// stage's records): the verdict (consistencyVerdict); and, when LS lies beyond --significance
/// standard errors of a consistent body, the optional-term test of `files` (each processed as
/// `signals`): a term the records show is a reason of its own, though the noise may explain the
/// distance, named with its option.
struct LsConsistency {
  ident::ConsistencyVerdict verdict;
  std::optional<ArmatureTest> armature;  ///< when tested
  std::string reason;                    ///< empty: nothing to say; else why LS must not be used, without the hint
  std::string hint;                      ///< the optional term's option, when the records show one
  /// "reason; hint" when the verdict is significant, else "hint (reason)": the armature leads and
  /// the distance, within the noise, is its context
  std::string problem() const;
};
LsConsistency judgeLeastSquares(const ChainIdentifyArgs& a, const LoadedChain& loaded, const LogInput& log, const ident::ChainEstimate& est,
                                const std::vector<std::string>& files, const std::vector<ident::SignalOptions>& signals, const std::string& whose);
/// identify's exit-3 reason when the nearest physically consistent estimate lies further from
/// `whose` estimate than the noise explains, in `errors` ("standard errors", "reported standard errors").
std::string inconsistencyProblem(const ident::ConsistencyVerdict& v, const std::string& whose, const char* errors);
/// How far a verdict's draws put the distance, for the printed line and the problem: "3 of 199
/// estimates drawn about a consistent body lie as far (p = 0.02)"; when not drawn, the half-normal
/// bound, or (beyond --significance: the draws could not be made) the distance alone.
std::string verdictText(const ident::ConsistencyVerdict& v);
/// The verdict as identify's JSON gives it (distance, p_value, draws, as_far, level, significant, seed).
nlohmann::json toJson(const ident::ConsistencyVerdict& v, std::uint64_t seed);

}  // namespace exoid::experiments
