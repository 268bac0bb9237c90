#pragma once
// The sweep's deterministic outputs from its job records, the APAL leg's or a chain's alike:
// runs.csv (one row per job x method), summary.csv / summary.json / summary.md (per condition and
// method: mean, std, 95 % Student-t CI; paired Wilcoxon comparison against LS; each parameter's
// error, its Cramer-Rao bound where the run gives one, and the coverage of the intervals).
// Nothing here depends on wall time, thread count, shard split or resume history, except the
// last column of runs.csv (wall_time_s).
#include "exoid/experiments/report/stats.hpp"
#include "exoid/experiments/sweep/sweep_config.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace exoid::experiments {

/// What the tables need to know of a sweep: its cells, methods and resolved configuration
/// (rebuilt from a folder's config.json by `exoid merge`).
struct SweepLayout {
  std::vector<SweepCondition> cells;
  int seeds = 0;
  nlohmann::json resolved;  ///< SweepConfig::toJson()
  /// A chain model's sweep (robot_sweep.hpp): its runs score the model's base parameters.
  bool chain = false;
  /// The methods in the sweep's order: Variant names (the APAL leg), ident::Method names (a chain).
  std::vector<std::string> method_names;
  const std::vector<SweepCondition>& conditions() const { return cells; }
};
SweepLayout layoutOf(const SweepConfig& c);
/// From a resolved configuration (config.json); throws std::runtime_error when malformed.
SweepLayout layoutFromJson(const nlohmann::json& resolved);

/// The per-run metrics the summary reports over seeds, in summary.csv's column order.
enum class SweepMetric {
  kTorqueErrHip,         ///< ||Y (x - x_bf)|| / ||Y x_bf|| on the validation states, hip (the APAL leg)
  kTorqueErrKnee,        ///< the same, knee (the APAL leg)
  kTorqueErrMean,        ///< mean over the joints (a chain: on its validation record)
  kMedianAbsRelErr,      ///< median over the parameters of |x_i - x_bf,i| / |x_bf,i|
  kMaxAbsRelErr,         ///< the largest of them
  kNormErrBestFit,       ///< ||x - x_bf|| / ||x_bf|| (Mxt-dominated, for comparison only)
  kNormErrRigid,         ///< ||x - x_rigid|| / ||x_rigid|| (idem)
  kGapBoxMax,            ///< worst stage's optimality gap against the L1 optimum over its box (APAL)
  kPlausibleRate,        ///< 1 when no physical condition is violated (APAL)
  kGapUnconstrainedMax,  ///< worst stage's gap against the unconstrained L1 optimum (APAL)
  kKneeValMeanAbs,       ///< knee validation (trajectory 2): mean |error|, N m (APAL)
  kKneeValRms,           ///< knee validation RMS error, N m (APAL)
  kHipValMeanAbs,        ///< hip validation (trajectory 4): mean |error|, N m (APAL)
  kHipValRms,            ///< hip validation RMS error, N m (APAL)
  kValRms,               ///< mean over the joints of the validation RMS errors, N m
};
inline constexpr int kNumSweepMetrics = 15;
/// Its name in summary.csv / summary.json ("torque_err_mean", ...).
const char* metricName(SweepMetric m);

/// A paired Wilcoxon signed-rank comparison of a method (or trajectory arm) against a reference
/// over the seeds both have. NaN where undefined (no pairs; mdd needs n >= 2).
struct PairedComparison {
  int n = 0;                                                 ///< paired seeds
  double win_rate = std::numeric_limits<double>::quiet_NaN();  ///< share of seeds with the lower value (ties 1/2)
  double p_value = std::numeric_limits<double>::quiet_NaN();   ///< two-sided
  double p_holm = std::numeric_limits<double>::quiet_NaN();    ///< Holm-adjusted over its family
  double mdd = std::numeric_limits<double>::quiet_NaN();  ///< minimal detectable mean difference, 80 % power, alpha 0.05
  bool exact = false;  ///< exact null distribution, else the normal approximation
};

/// a against b, seed by seed (a[i] and b[i] of the same seed): win rate, Wilcoxon signed-rank p
/// and the minimal detectable difference (p_holm left for holmAdjustFamily).
PairedComparison pairedValues(const std::vector<double>& a, const std::vector<double>& b);
/// Holm-adjusts a family of tests (a null member is a missing test: NaN in the family).
void holmAdjustFamily(const std::vector<PairedComparison*>& family);

/// A method against LS in the same cell (the torque error, the validation RMS and the median
/// parameter error); Holm's family: the sweep's cells, per method and metric.
struct VersusLs {
  PairedComparison torque_err_mean, val_rms, median_abs_rel_err;
};

/// One metric of an optimised cell against its paper twin, and both arms' means over seeds.
struct VersusPaper {
  PairedComparison test;
  double optimised_mean = std::numeric_limits<double>::quiet_NaN();
  double paper_mean = std::numeric_limits<double>::quiet_NaN();
};
/// An optimised-trajectories cell against the paper cell of the same condition and seeds; Holm's
/// family: the compared cells, per method and metric (each parameter's |error| is a metric).
struct TrajectoryComparison {
  int paper_cell = -1;
  VersusPaper torque_err_mean, median_abs_rel_err, max_abs_rel_err, val_rms;
  std::vector<VersusPaper> parameters;  ///< |relative error| of each parameter
};

/// One parameter over a method's seeds.
struct ParameterStatistics {
  stats::ConfidenceInterval rel_err;  ///< signed relative error against the best fit (std unused)
  double abs_rel_err_median = std::numeric_limits<double>::quiet_NaN();
  double abs_rel_err_max = std::numeric_limits<double>::quiet_NaN();
  double abs_err_rms = std::numeric_limits<double>::quiet_NaN();  ///< RMS of x - truth (a zero truth has no relative error)
  double crb_std = std::numeric_limits<double>::quiet_NaN();             ///< mean noise-limited std
  double rms_error_over_crb = std::numeric_limits<double>::quiet_NaN();  ///< RMS of error / that seed's CRB std
  /// How often estimate -+ 1.96 CRB std held the best-fit truth (the interval the noise alone
  /// would justify), the mean error and the scatter in those stds.
  stats::Coverage coverage;
  /// The same with the standard errors the method reports (segmental LS: identify's rule stage by
  /// stage); n = 0 for a method that reports none.
  stats::Coverage coverage_reported;
};

/// Coverage below this share of the runs names the parameter in summary.md's verdict: a nominal
/// 95 % interval that holds the truth in fewer than 90 % of 200 runs is short by 4 binomial
/// standard deviations, not by chance.
inline constexpr double kCoverageShortfall = 0.90;

/// A parameter's coverage in summary.json: n, share, its Wilson interval, the mean error and the
/// scatter in sigmas.
nlohmann::json coverageJson(const stats::Coverage& c);
/// "Mxt 43 % [36, 50] (mean error -3.3 sigma, scatter 1.1 sigma), ..." for every parameter whose
/// coverage is short of kCoverageShortfall ("" when none is).
std::string coverageShortfall(const std::vector<std::string>& names, const std::vector<stats::Coverage>& coverage);

/// One method in one cell, over the seeds where it gave an estimate.
struct MethodSummary {
  std::string method;
  int n = 0;         ///< seeds with an estimate
  int n_failed = 0;  ///< seeds without
  std::array<stats::ConfidenceInterval, kNumSweepMetrics> metrics;  ///< indexed by SweepMetric
  std::vector<ParameterStatistics> parameters;  ///< in the cell's parameter order (CellSummary::parameters)
  double rms_error_over_crb_max = std::numeric_limits<double>::quiet_NaN();  ///< worst parameter's
  std::optional<VersusLs> vs_ls;  ///< not for LS itself, nor where LS has no estimate
  std::optional<TrajectoryComparison> vs_paper_trajectories;  ///< optimised cells with a paper twin only
  const stats::ConfidenceInterval& metric(SweepMetric m) const { return metrics[static_cast<std::size_t>(m)]; }
};

/// One grid cell that has at least one job.
struct CellSummary {
  int cell = 0;
  SweepCondition condition;
  std::vector<std::string> parameters;  ///< the parameters scored: X, or the chain's base parameters
  std::vector<double> truth;            ///< a chain's (the same every run); empty for the APAL leg (per run)
  std::vector<MethodSummary> methods;   ///< in the sweep's method order
  /// nullptr when the sweep did not run `method`.
  const MethodSummary* find(const std::string& method) const;
  /// Throws std::out_of_range when the sweep did not run `method`.
  const MethodSummary& method(const std::string& method) const;
};

/// The sweep summarised per cell and method: what summary.json, summary.csv and summary.md show.
struct SweepSummary {
  SweepLayout layout;
  std::vector<CellSummary> cells;  ///< by cell index
};

/// `jobs` sorted by (cell, replicate).
SweepSummary summarizeSweep(const SweepLayout& config, const std::vector<nlohmann::json>& jobs);
/// What summary.json holds: the tool, the resolved configuration, how each statistic is computed,
/// and the cells (NaN as null).
nlohmann::json toJson(const SweepSummary& s);

/// `jobs` sorted by (cell, replicate). Writes runs.csv, summary.csv, summary.json, summary.md
/// into `dir` (atomically, file by file).
void writeSweepTables(const SweepLayout& config, const std::vector<nlohmann::json>& jobs, const std::string& dir);

}  // namespace exoid::experiments
