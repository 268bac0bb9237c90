#pragma once
// Identification runs as the CLI and the experiments use them: one method on one record (all
// 10 parameters from both equations) or the paper's segmental strategy, plus their JSON form.
#include "exoid/ident/estimators/idim_iv.hpp"
#include "exoid/ident/estimators/methods.hpp"
#include "exoid/ident/estimators/standard_errors.hpp"
#include "exoid/ident/estimators/standard_errors.hpp"
#include "exoid/ident/leg/consistency.hpp"
#include "exoid/ident/leg/metrics.hpp"
#include "exoid/ident/leg/regressor.hpp"
#include "exoid/ident/model/determination.hpp"
#include "exoid/ident/signals/processing.hpp"

#include <nlohmann/json.hpp>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace exoid::experiments {

/// One estimator call and which entries of X it estimated.
struct Stage {
  std::string name;          ///< "all", "knee", "hip"
  std::vector<int> indices;  ///< into the 10-vector X; ident::kKneeArmature for Ia2
  ident::Estimate estimate;
};

/// The physically consistent step of a least-squares fit of all parameters (identify's default):
/// the unconstrained estimate, its standard errors from its own residuals (Newey-West) and the
/// constrained estimate with each condition's distance in those standard errors.
/// What the reported standard errors are, in words (identify's JSON and console).
extern const char* const kReportedErrorsAre;
/// The same for a segmental fit (MethodOutcome::segmental_errors).
extern const char* const kSegmentalErrorsAre;

struct ConsistencyStep {
  Eigen::VectorXd unconstrained;  ///< 10 (or 11 with Ia2)
  Eigen::VectorXd std_err;        ///< of the unconstrained estimate: errors.reported
  ident::ReportedErrors errors;   ///< Newey-West's, the block jackknife's, and which was reported
  ident::ConsistentEstimate fit;
  double significance_sigmas = 2.0;
  /// Conditions violated beyond significance_sigmas ("... violated by 3.1 standard errors ...").
  std::vector<std::string> significant() const { return fit.significantViolations(significance_sigmas); }
  /// Conditions violated within significance_sigmas: consistent with the bound (the constrained
  /// estimate sits on it).
  std::vector<std::string> withinNoise() const;
};

struct MethodOutcome {
  ident::Method method = ident::Method::kLs;
  ident::ParamVector x = ident::ParamVector::Zero();
  /// Ia2 (ident::kKneeArmature), when the knee armature was estimated.
  std::optional<double> knee_armature;
  std::vector<Stage> stages;
  /// Violated physical conditions of x (ident::implausibilities; parameters a stage could not
  /// identify are not checked). Non-empty: the estimate cannot be the leg's.
  std::vector<std::string> implausible;
  /// Set when the estimate was made physically consistent (applyConsistency): x (and Ia2) are then
  /// the constrained estimate, and `implausible` lists only the significant violations.
  std::optional<ConsistencyStep> consistency;
  /// LS by the segmental strategy: the reported errors of x (ident::segmentalReportedErrors).
  std::optional<ident::ReportedErrors> segmental_errors;
  bool usable() const;        ///< every stage usable
  std::string problems() const;  ///< the messages of unusable stages
  double wallTime_s() const;
};

/// An optional term the records may need, on every leg: an armature (a geared motor's reflected
/// rotor inertia, Ia qdd on its joint's own diagonal) on each joint the model gives none, fitted
/// by LS with the model. Each that is a parameter of its own (not regrouped into a link's
/// inertia) and lies more than the significance in reported errors above 0 (a rotor inertia is
/// positive) is named, with the option that adds it.
struct ArmatureTest {
  nlohmann::json json = nlohmann::json::object();  ///< per joint tested: value_kgm2, std_error_kgm2, significant, threshold_sigmas
  std::vector<std::string> joints, shown;           ///< the significant ones; "knee.Ia = 0.1 +- 0.01 kg m^2, 10 standard errors above 0"
  bool two_link = false;                            ///< the APAL leg: its option is --knee-armature
  std::string hint() const;  ///< "...: rerun with --armature knee,ankle" (--knee-armature); empty: none
};
/// `with` is the robot with an armature on each of `joints` (the 2-link leg's is Ia2, a chain's
/// "<joint>.Ia"; std::invalid_argument for another joint of the 2-link leg); rows its rows of each
/// record (each processed in its own band). Nothing is tested when that fit is not full rank. An
/// armature is significant above the Bonferroni threshold of significance_sigmas (one-sided) over
/// the joints tested (bonferroniZ: significance_sigmas itself for one).
ArmatureTest armatureTest(const ident::Robot& with, const std::vector<ident::RecordRows>& rows, const std::vector<std::string>& joints,
                          double significance_sigmas, double max_condition);

/// Reported errors as identify's JSON gives them, by parameter name: standard_errors (the
/// reported), _newey_west, _jackknife, _record_jackknife, _from, _are.
nlohmann::json errorsJson(const ident::ReportedErrors& e, const char* are);

/// Entries of a search-box estimate (PSO, RLS-PSO) on their box's bound (within 1e-9 of the box
/// width): there the box, not the data, chose the value, and the cost's optimum lies outside.
/// The entries of one estimate on its box's bound (a PSO or RLS-PSO estimate with a box; none
/// for other methods), by index into its x.
std::vector<Eigen::Index> boxBoundIndices(const ident::Estimate& e);
/// "name = 50 is on its box's bound [-50, 50]" for entry i of e.
std::string boxBoundMessage(const std::string& name, const ident::Estimate& e, Eigen::Index i);
struct BoundHit {
  std::string stage;
  int param = 0;  ///< index into X
  double value = 0.0, lower = 0.0, upper = 0.0;
};
std::vector<BoundHit> boxBoundHits(const MethodOutcome& m);
/// "Mxt = 50 is on its box's bound [-50, 50]".
std::string describe(const BoundHit& h);

/// All parameters from every equation of one record (rows in time order): the 10 of X, and Ia2
/// when the rows have the knee armature's column (a robot made with it: ident::twoLinkLeg).
MethodOutcome identifyAll(ident::Method m, const ident::RecordRows& r, const ident::MethodOptions& o);
/// The outcome of an estimate of all parameters made elsewhere (iv-band), stage "all".
MethodOutcome identifyAll(ident::Estimate e, bool knee_armature = false);
/// The paper's segmental strategy: the knee parameters from knee_record (hip fixed), the hip's
/// from both_record's hip equation with the knee part subtracted (ident::identifySegmental).
MethodOutcome identifySegmented(const ident::Robot& robot, ident::Method m, const ident::RecordRows& knee_record,
                                const ident::RecordRows& both_record, const ident::MethodOptions& o);
/// IDIM-IV with the segmental strategy (ident::identifySegmentalIdimIv): stages "knee" and "hip".
MethodOutcome identifySegmentedIdimIv(const ident::Robot& robot, const ident::ClosedLoopRecord& knee_record,
                                      const ident::ClosedLoopRecord& both_record, const ident::IvOptions& options);
/// IDIM-IV on every equation of one record, all parameters (stage "all").
MethodOutcome identifyAllIdimIv(const ident::Robot& robot, const ident::ClosedLoopRecord& record, const ident::IvOptions& options);

/// The reported errors of x fitted to the 2-link leg's rows p (both equations of a sample one step
/// of one channel; each record's blocks for the jackknife): what identify reports of LS.
ident::ReportedErrors legReportedErrors(const ident::RecordRows& p, const Eigen::VectorXd& x);

/// Makes m (an all-parameter LS fit of the rows of r) physically consistent: standard errors from
/// the residuals, ident::solveConsistentLeastSquares, m.x the constrained estimate; a violation
/// within options.significance_sigmas is consistent with the bound, a larger one stays in
/// m.implausible (not usable). Throws std::invalid_argument unless m has one stage "all".
void applyConsistency(MethodOutcome& m, const ident::RecordRows& r, const ident::LegConstants& c,
                      const ident::ConsistencyOptions& options = {});
/// The same for the segmental strategy's LS (m.segmental_errors set, 10 parameters): its stages have
/// no common rows, so the consistent estimate is the nearest consistent x in the metric of the
/// reported covariance C, min (x' - x)' C^-1 (x' - x), and each condition is judged by its
/// distance in the reported errors. Nothing changes when C is not finite and positive definite.
void applySegmentalConsistency(MethodOutcome& m, const ident::LegConstants& c, const ident::ConsistencyOptions& options = {});

/// Each joint's torque error of theta (every parameter of the rows' robot: std::invalid_argument
/// when its size is not the rows' columns) on a record.
std::vector<ident::TorqueErrorStats> jointTorqueErrors(const ident::RecordRows& r, const Eigen::VectorXd& theta);

/// Per-joint validation torque errors of X on a record.
struct Validation {
  ident::TorqueErrorStats hip;
  ident::TorqueErrorStats knee;
};
/// knee_armature: Ia2 (its term Ia2 qdd2 joins the knee prediction; the rows then have its column).
Validation validate(const ident::RecordRows& r, const ident::ParamVector& x, double knee_armature = 0.0);

/// {"Mxt": ..., ...} and back (all 10 names required; unknown names rejected with the name).
nlohmann::json paramsJson(const ident::ParamVector& x);
nlohmann::json paramsJson(const Eigen::VectorXd& values, const std::vector<int>& indices);
ident::ParamVector paramsFromJson(const nlohmann::json& j, const std::string& where);

nlohmann::json toJson(const ident::TorqueErrorStats& s);
nlohmann::json toJson(const Validation& v);
nlohmann::json toJson(const ident::ParamError& e);
/// What an estimate says besides its values, on any robot: status, message, iterations, L1 cost,
/// wall time, rank, condition number, the optimality gaps, PSO's initial cost and (with_history)
/// best-cost history, IDIM-IV's steps.
nlohmann::json estimateJson(const ident::Estimate& e, bool with_history);
/// estimateJson with the stage's name, its parameters and box by name, what it could not identify.
nlohmann::json toJson(const Stage& s, bool with_history);
nlohmann::json toJson(const MethodOutcome& m, bool with_history);

/// Named truth vectors from a JSON file: {"parameters": {...}} (named "truth"), or a simulation
/// sidecar's {"truth": {"<name>": {"parameters": {...}}, ...}}. Errors name the file and key.
std::map<std::string, ident::ParamVector> readTruthFile(const std::string& path);

/// {"name": "exoid", "version": ..., "revision": ...}
nlohmann::json toolJson();
/// Writes pretty JSON atomically.
void writeJsonFile(const std::string& path, const nlohmann::json& j);
/// j without its "wall_time_s" entries, at any depth: the one part two runs of one job need not share.
nlohmann::json withoutWallTimes(nlohmann::json j);
/// The JSON file at path; std::runtime_error naming it when it cannot be read or parsed.
nlohmann::json readJsonFile(const std::string& path);
/// A JSON file the user gave (a controller, a design, a truth, an identification), `what` naming
/// it: std::invalid_argument "PATH: cannot open the WHAT" or "PATH: not valid JSON: ...".
nlohmann::json readUserJsonFile(const std::string& path, const std::string& what);

/// Which parameters the records determine by their own motion (ident/model/determination.hpp),
/// as identify's JSON gives it: each record's file (`files`, in d.records' order), joints (range,
/// noise, floor, moved) and the parameters not determined.
nlohmann::json determinationJson(const ident::Robot& robot, const ident::Determination& d, const std::vector<std::string>& files);
/// identify's exit-3 reason when some requested parameter is not determined ("" when all are).
std::string undeterminedProblem(const ident::Robot& robot, const ident::Determination& d);

}  // namespace exoid::experiments
