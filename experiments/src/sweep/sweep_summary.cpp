#include "exoid/experiments/sweep/sweep_summary.hpp"

#include "exoid/core/format.hpp"
#include "exoid/experiments/sweep/fault_injection.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/report/cells.hpp"
#include "exoid/experiments/report/stats.hpp"
#include "exoid/experiments/report/table.hpp"
#include "exoid/core/atomic_file.hpp"
#include "exoid/ident/leg/metrics.hpp"
#include "exoid/ident/leg/params.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <ostream>

namespace exoid::experiments {

PairedComparison pairedValues(const std::vector<double>& a, const std::vector<double>& b) {
  PairedComparison p;
  p.n = static_cast<int>(a.size());
  if (a.empty()) return p;
  double wins = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) wins += a[i] < b[i] ? 1.0 : (a[i] == b[i] ? 0.5 : 0.0);
  p.win_rate = wins / static_cast<double>(a.size());
  std::vector<double> diff(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) diff[i] = a[i] - b[i];
  p.mdd = stats::minimalDetectableDifference(stats::sampleStd(diff), p.n);
  const stats::WilcoxonResult w = stats::wilcoxonSignedRank(a, b);
  p.p_value = w.p_value;
  p.exact = w.exact;
  return p;
}

void holmAdjustFamily(const std::vector<PairedComparison*>& family) {
  std::vector<double> ps;
  for (const PairedComparison* t : family) ps.push_back(t != nullptr && std::isfinite(t->p_value) ? t->p_value : std::numeric_limits<double>::quiet_NaN());
  const std::vector<double> adj = stats::holmAdjust(ps);
  for (std::size_t k = 0; k < family.size(); ++k) {
    if (family[k] != nullptr) family[k]->p_holm = adj[k];
  }
}

nlohmann::json coverageJson(const stats::Coverage& c) {
  return {{"n", c.n},
          {"share", jsonNumber(c.share)},
          {"wilson95_low", jsonNumber(c.low)},
          {"wilson95_high", jsonNumber(c.high)},
          {"mean_error_over_sigma", jsonNumber(c.mean_error_over_sigma)},
          {"sd_over_mean_sigma", jsonNumber(c.sd_over_mean_sigma)}};
}

std::string coverageShortfall(const std::vector<std::string>& names, const std::vector<stats::Coverage>& coverage) {
  std::string out;
  for (std::size_t i = 0; i < names.size() && i < coverage.size(); ++i) {
    const stats::Coverage& c = coverage[i];
    if (c.n == 0 || !(c.share < kCoverageShortfall)) continue;
    out += (out.empty() ? "" : ", ") + names[i] + " " + fixed(100.0 * c.share, 0) + " % [" + fixed(100.0 * c.low, 0) + ", " +
           fixed(100.0 * c.high, 0) + "] (mean error " + fmt(c.mean_error_over_sigma, 2) + " sigma, scatter " +
           fmt(c.sd_over_mean_sigma, 2) + " sigma)";
  }
  return out;
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Scores of one (job, method), recomputed from the stored raw numbers. The parameter vectors have
// the run's parameters (X, or a chain's base parameters); what a run does not score is NaN.
struct Row {
  int cell = 0, replicate = 0;
  std::uint64_t seed = 0;
  std::string method, status, message;
  bool ok = false;
  double err_rigid = kNaN, err_best_fit = kNaN;  // norms: Mxt-dominated, kept under that name
  Eigen::VectorXd rel_best_fit, rel_rigid, abs_best_fit;
  Eigen::VectorXd crb;       // this method's noise std
  Eigen::VectorXd z;         // abs_best_fit / crb
  Eigen::VectorXd reported;  // the method's own standard errors, if any
  double ts_hip = kNaN, ts_knee = kNaN, ts_mean = kNaN;  // torque-space vs best fit
  double gap_box = kNaN, gap_free = kNaN;                // worst stage
  double median_abs_rel = kNaN, max_abs_rel = kNaN;
  double plausible = kNaN;  // 1 when no physical condition is violated
  double val[6] = {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};  // knee mean/std/rms, hip mean/std/rms
  double val_rms = kNaN;                                 // mean over the joints
  double wall_time_s = kNaN;
};

Eigen::VectorXd vec(const nlohmann::json& j) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(j.size()));
  for (std::size_t i = 0; i < j.size(); ++i) v[static_cast<Eigen::Index>(i)] = j[i].get<double>();
  return v;
}

double jsonMean(const nlohmann::json& values) { return stats::mean(values.get<std::vector<double>>()); }

// Median and worst |relative error| over the parameters that have one.
void summarizeRelativeErrors(Row& r) {
  std::vector<double> a;
  for (Eigen::Index i = 0; i < r.rel_best_fit.size(); ++i) {
    if (!std::isnan(r.rel_best_fit[i])) a.push_back(std::abs(r.rel_best_fit[i]));
  }
  if (a.empty()) return;
  r.max_abs_rel = *std::max_element(a.begin(), a.end());
  r.median_abs_rel = stats::median(a);
}

// The APAL protocol's scores of a method: the errors against the rigid and the best-fit truth,
// CRB, torque-space errors, optimality gaps, the paper's validation trajectories.
void readApalScores(const nlohmann::json& job, const nlohmann::json& m, Row& r) {
  const Eigen::VectorXd x = vec(m.at("x"));
  const ident::ParamError eb = ident::paramError(x, vec(job.at("truth").at("best_fit")));
  const ident::ParamError er = ident::paramError(x, vec(job.at("truth").at("rigid")));
  r.err_best_fit = eb.norm_rel;
  r.err_rigid = er.norm_rel;
  r.rel_best_fit = eb.rel;
  r.rel_rigid = er.rel;
  r.abs_best_fit = eb.abs;
  r.crb = vec(m.at("crb_std"));
  r.reported = m.contains("std_error") ? vec(m.at("std_error")) : Eigen::VectorXd::Constant(x.size(), kNaN);
  r.plausible = m.at("implausible").empty() ? 1.0 : 0.0;
  r.z.resize(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) r.z[i] = r.crb[i] > 0.0 ? r.abs_best_fit[i] / r.crb[i] : kNaN;
  r.ts_hip = m.at("torque_space").at("best_fit").at("hip").get<double>();
  r.ts_knee = m.at("torque_space").at("best_fit").at("knee").get<double>();
  r.ts_mean = 0.5 * (r.ts_hip + r.ts_knee);
  for (const auto& [stage, g] : m.at("optimality_gaps").items()) {
    if (g.contains("box")) r.gap_box = std::isnan(r.gap_box) ? g["box"].get<double>() : std::max(r.gap_box, g["box"].get<double>());
    if (g.contains("unconstrained")) {
      r.gap_free = std::isnan(r.gap_free) ? g["unconstrained"].get<double>() : std::max(r.gap_free, g["unconstrained"].get<double>());
    }
  }
  int k = 0;
  for (const char* joint : {"knee_validation", "hip_validation"}) {
    for (const char* f : {"mean_abs", "std_abs", "rms"}) r.val[k++] = m.at(joint).at(f).get<double>();
  }
  r.val_rms = 0.5 * (r.val[2] + r.val[5]);
  r.wall_time_s = m.at("wall_time_s").get<double>();
}

// A chain run's scores of a method (robot_sweep.hpp): errors against the simulation's truth, the
// validation record's torque errors per joint, LS's own standard errors. A base parameter's error
// is relative (to |truth|) unless its truth is zero (up to rounding of the combination): then only
// its absolute error counts.
void readChainScores(const nlohmann::json& job, const nlohmann::json& m, Row& r) {
  const Eigen::VectorXd truth = vec(job.at("truth"));
  const Eigen::Index n = truth.size();
  r.crb = r.z = r.reported = r.rel_best_fit = r.abs_best_fit = Eigen::VectorXd::Constant(n, kNaN);
  if (!r.ok) return;
  const Eigen::VectorXd x = vec(m.at("x"));
  r.abs_best_fit = x - truth;
  const double zero = 1e-12 * truth.cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < n; ++i) r.rel_best_fit[i] = std::abs(truth[i]) > zero ? r.abs_best_fit[i] / std::abs(truth[i]) : kNaN;
  if (m.contains("std_error")) r.reported = vec(m.at("std_error"));
  r.ts_mean = jsonMean(m.at("torque_err_rel"));
  r.val_rms = jsonMean(m.at("val_rms_Nm"));
}

std::vector<Row> rowsOf(const SweepLayout& config, const std::vector<nlohmann::json>& jobs) {
  std::vector<Row> rows;
  for (const nlohmann::json& job : jobs) {
    Row base;
    base.cell = job.at("cell").get<int>();
    base.replicate = job.at("replicate").get<int>();
    base.seed = job.at("seed").get<std::uint64_t>();
    if (job.at("status") != "ok") {
      for (const std::string& method : config.method_names) {
        Row r = base;
        r.method = method;
        r.status = "error";
        r.message = job.at("message").get<std::string>();
        rows.push_back(r);
      }
      continue;
    }
    for (const nlohmann::json& m : job.at("methods")) {
      Row r = base;
      r.method = m.at("method").get<std::string>();
      r.status = m.at("status").get<std::string>();
      r.message = m.at("message").get<std::string>();
      r.ok = r.status == "ok";
      if (config.chain) {
        readChainScores(job, m, r);
        r.wall_time_s = job.at("wall_time_s").get<double>();  // a chain run's methods share one record and one time
      } else {
        readApalScores(job, m, r);
      }
      summarizeRelativeErrors(r);
      rows.push_back(r);
    }
  }
  return rows;
}

// Each cell's parameters: the APAL leg's X in every cell; a chain's base parameters (and truth)
// from the cell's first successful run (none when every run failed).
struct CellParameters {
  std::vector<std::string> names;
  std::vector<double> truth;
};

std::map<int, CellParameters> parametersOf(const SweepLayout& config, const std::vector<nlohmann::json>& jobs) {
  std::map<int, CellParameters> out;
  if (!config.chain) {
    CellParameters x;
    for (int i = 0; i < ident::kNumParams; ++i) x.names.emplace_back(ident::paramName(i));
    for (std::size_t cell = 0; cell < config.cells.size(); ++cell) out[static_cast<int>(cell)] = x;
    return out;
  }
  for (const nlohmann::json& job : jobs) {
    const int cell = job.at("cell").get<int>();
    if (job.at("status") != "ok" || out.count(cell)) continue;
    out[cell] = {job.at("base_parameters").get<std::vector<std::string>>(), job.at("truth").get<std::vector<double>>()};
  }
  return out;
}

// The summary metrics, in SweepMetric order: how to read each from a row.
struct Metric {
  SweepMetric id;
  const char* name;
  double (*get)(const Row&);
};
constexpr Metric kMetrics[kNumSweepMetrics] = {
    {SweepMetric::kTorqueErrHip, "torque_err_hip", [](const Row& r) { return r.ts_hip; }},
    {SweepMetric::kTorqueErrKnee, "torque_err_knee", [](const Row& r) { return r.ts_knee; }},
    {SweepMetric::kTorqueErrMean, "torque_err_mean", [](const Row& r) { return r.ts_mean; }},
    {SweepMetric::kMedianAbsRelErr, "median_abs_rel_err", [](const Row& r) { return r.median_abs_rel; }},
    {SweepMetric::kMaxAbsRelErr, "max_abs_rel_err", [](const Row& r) { return r.max_abs_rel; }},
    {SweepMetric::kNormErrBestFit, "norm_err_best_fit_mxt_dominated", [](const Row& r) { return r.err_best_fit; }},
    {SweepMetric::kNormErrRigid, "norm_err_rigid_mxt_dominated", [](const Row& r) { return r.err_rigid; }},
    {SweepMetric::kGapBoxMax, "gap_box_max", [](const Row& r) { return r.gap_box; }},
    {SweepMetric::kPlausibleRate, "plausible_rate", [](const Row& r) { return r.plausible; }},
    {SweepMetric::kGapUnconstrainedMax, "gap_unconstrained_max", [](const Row& r) { return r.gap_free; }},
    {SweepMetric::kKneeValMeanAbs, "knee_val_mean_abs", [](const Row& r) { return r.val[0]; }},
    {SweepMetric::kKneeValRms, "knee_val_rms", [](const Row& r) { return r.val[2]; }},
    {SweepMetric::kHipValMeanAbs, "hip_val_mean_abs", [](const Row& r) { return r.val[3]; }},
    {SweepMetric::kHipValRms, "hip_val_rms", [](const Row& r) { return r.val[5]; }},
    {SweepMetric::kValRms, "val_rms", [](const Row& r) { return r.val_rms; }},
};

constexpr bool inSweepMetricOrder() {
  for (int i = 0; i < kNumSweepMetrics; ++i) {
    if (static_cast<int>(kMetrics[i].id) != i) return false;
  }
  return true;
}
static_assert(inSweepMetricOrder(), "kMetrics lists the metrics in SweepMetric order (MethodSummary::metrics is indexed by it)");

double metricOf(const Row& r, SweepMetric m) { return kMetrics[static_cast<std::size_t>(m)].get(r); }

// The paired comparisons against LS, and against the paper's trajectories: metric and field.
struct LsPaired {
  SweepMetric metric;
  PairedComparison VersusLs::*field;
};
const LsPaired kVersusLs[] = {{SweepMetric::kTorqueErrMean, &VersusLs::torque_err_mean},
                              {SweepMetric::kValRms, &VersusLs::val_rms},
                              {SweepMetric::kMedianAbsRelErr, &VersusLs::median_abs_rel_err}};
struct PaperPaired {
  SweepMetric metric;
  VersusPaper TrajectoryComparison::*field;
};
const PaperPaired kVersusPaper[] = {{SweepMetric::kTorqueErrMean, &TrajectoryComparison::torque_err_mean},
                                    {SweepMetric::kMedianAbsRelErr, &TrajectoryComparison::median_abs_rel_err},
                                    {SweepMetric::kMaxAbsRelErr, &TrajectoryComparison::max_abs_rel_err},
                                    {SweepMetric::kValRms, &TrajectoryComparison::val_rms}};

using Replicates = std::map<int, const Row*>;  // replicate -> row (ok only)
struct Cell {
  std::map<std::string, Replicates> by_method;
  std::map<std::string, int> failed;
};

std::map<int, Cell> cellsOf(const std::vector<Row>& rows) {
  std::map<int, Cell> cells;
  for (const Row& r : rows) {
    Cell& c = cells[r.cell];
    if (r.ok) {
      c.by_method[r.method][r.replicate] = &r;
    } else {
      ++c.failed[r.method];
    }
  }
  return cells;
}

const Replicates& repsOf(const Cell& c, const std::string& method) {
  static const Replicates empty;
  const auto it = c.by_method.find(method);
  return it == c.by_method.end() ? empty : it->second;
}

// The names of every list, in the order they first appear: the columns of runs.csv and
// summary.csv (a chain's vibrating cells add their base-motion parameters).
std::vector<std::string> allNames(const std::vector<const std::vector<std::string>*>& lists) {
  std::vector<std::string> names;
  for (const std::vector<std::string>* list : lists) {
    for (const std::string& n : *list) {
      if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
    }
  }
  return names;
}

// Where each of `names` sits in a cell's own parameters (own.size() where the cell lacks it).
std::vector<std::size_t> positions(const std::vector<std::string>& names, const std::vector<std::string>& own) {
  std::vector<std::size_t> at;
  for (const std::string& n : names) at.push_back(static_cast<std::size_t>(std::find(own.begin(), own.end(), n) - own.begin()));
  return at;
}

void writeRunsCsv(const SweepLayout& config, const std::vector<Row>& rows, const std::map<int, CellParameters>& cells, const std::string& path) {
  const std::vector<SweepCondition> conds = config.conditions();
  std::vector<const std::vector<std::string>*> lists;
  for (const auto& [cell, p] : cells) lists.push_back(&p.names);
  const std::vector<std::string> names = allNames(lists);
  static const std::vector<std::string> kNone;
  core::writeFileAtomically(path, [&](std::ostream& out) {
    out << "cell,replicate," << kConditionCsvHeader
        << ",seed,method,status,torque_err_hip,torque_err_knee,median_abs_rel_err,max_abs_rel_err,"
           "norm_err_rigid_mxt_dominated,norm_err_best_fit_mxt_dominated,gap_box_max,gap_unconstrained_max,plausible";
    for (const char* prefix : {"rel_err_", "rel_err_rigid_", "err_over_crb_", "crb_std_"}) {
      for (const std::string& n : names) out << ',' << csvField(prefix + n);
    }
    out << ",knee_val_mean_abs,knee_val_std_abs,knee_val_rms,hip_val_mean_abs,hip_val_std_abs,hip_val_rms,torque_err_mean,val_rms";
    for (const std::string& n : names) out << ',' << csvField("err_" + n);
    out << ",message,wall_time_s\n";
    for (const Row& r : rows) {
      out << r.cell << ',' << r.replicate << ',' << conditionCsv(conds[static_cast<std::size_t>(r.cell)]) << ',' << r.seed << ','
          << r.method << ',' << r.status << ',' << csvNumber(r.ts_hip) << ',' << csvNumber(r.ts_knee) << ',' << csvNumber(r.median_abs_rel)
          << ',' << csvNumber(r.max_abs_rel) << ',' << csvNumber(r.err_rigid) << ',' << csvNumber(r.err_best_fit) << ',' << csvNumber(r.gap_box) << ','
          << csvNumber(r.gap_free) << ',' << csvNumber(r.plausible);
      const auto own = cells.find(r.cell);
      const std::vector<std::size_t> at = positions(names, own == cells.end() ? kNone : own->second.names);
      const auto byName = [&](const Eigen::VectorXd& v) {
        for (const std::size_t i : at) out << ',' << csvNumber(static_cast<Eigen::Index>(i) < v.size() ? v[static_cast<Eigen::Index>(i)] : kNaN);
      };
      for (const Eigen::VectorXd* v : {&r.rel_best_fit, &r.rel_rigid, &r.z, &r.crb}) byName(*v);
      for (double v : r.val) out << ',' << csvNumber(v);
      out << ',' << csvNumber(r.ts_mean) << ',' << csvNumber(r.val_rms);
      byName(r.abs_best_fit);
      out << ',' << csvField(r.message) << ',' << csvNumber(r.wall_time_s) << '\n';
    }
  });
}

// ---- The summary's statistics ----


// `m` against `ref` over the replicates both have, on a value of a row.
template <typename Get>
PairedComparison pairedBy(const Replicates& m, const Replicates& ref, Get get) {
  std::vector<double> a, b;
  for (const auto& [rep, row] : m) {
    const auto it = ref.find(rep);
    if (it == ref.end()) continue;
    a.push_back(get(*row));
    b.push_back(get(*it->second));
  }
  return pairedValues(a, b);
}

// Mean over the replicates of the finite values of a row's value.
template <typename Get>
double meanOf(const Replicates& reps, Get get) {
  std::vector<double> x;
  for (const auto& [rep, row] : reps) {
    if (std::isfinite(get(*row))) x.push_back(get(*row));
  }
  return stats::mean(x);
}

stats::ConfidenceInterval metricCi(const Replicates& reps, SweepMetric m) {
  std::vector<double> x;
  for (const auto& [rep, row] : reps) {
    if (std::isfinite(metricOf(*row, m))) x.push_back(metricOf(*row, m));
  }
  return stats::meanCi(x);
}

// Parameter i over a method's seeds: signed relative error (mean, CI; a zero truth has none),
// median and worst |rel|, RMS of the error, mean noise std (CRB) and RMS of error / CRB.
ParameterStatistics parameterStatistics(const Replicates& reps, Eigen::Index i) {
  std::vector<double> rel, abs_rel, crb, errors, sigmas, reported;
  double z2 = 0.0, e2 = 0.0;
  int zn = 0;
  for (const auto& [rep, row] : reps) {
    errors.push_back(row->abs_best_fit[i]);
    e2 += row->abs_best_fit[i] * row->abs_best_fit[i];
    sigmas.push_back(row->crb[i]);
    reported.push_back(row->reported[i]);
    if (!std::isnan(row->rel_best_fit[i])) {
      rel.push_back(row->rel_best_fit[i]);
      abs_rel.push_back(std::abs(row->rel_best_fit[i]));
    }
    if (std::isfinite(row->crb[i])) crb.push_back(row->crb[i]);
    if (std::isfinite(row->z[i])) {
      z2 += row->z[i] * row->z[i];
      ++zn;
    }
  }
  ParameterStatistics p;
  p.rel_err = stats::meanCi(rel);
  p.abs_rel_err_median = stats::median(abs_rel);
  p.abs_rel_err_max = abs_rel.empty() ? kNaN : *std::max_element(abs_rel.begin(), abs_rel.end());
  p.abs_err_rms = reps.empty() ? kNaN : std::sqrt(e2 / static_cast<double>(reps.size()));
  p.crb_std = stats::mean(crb);
  p.rms_error_over_crb = zn ? std::sqrt(z2 / zn) : kNaN;
  p.coverage = stats::coverageOf(errors, sigmas);
  p.coverage_reported = stats::coverageOf(errors, reported);
  return p;
}

// The largest finite RMS error / CRB over the parameters (NaN when none is).
double worstOverCrb(const std::vector<ParameterStatistics>& parameters) {
  double worst = kNaN;
  for (const ParameterStatistics& p : parameters) {
    const double r = p.rms_error_over_crb;
    if (std::isfinite(r)) worst = std::isfinite(worst) ? std::max(worst, r) : r;
  }
  return worst;
}

// One method in one cell of `parameters` parameters; `ls` is LS's replicates in the same cell
// (compared when not empty).
MethodSummary summarizeMethod(const Cell& c, const std::string& name, const Replicates& ls, std::size_t parameters) {
  const Replicates& reps = repsOf(c, name);
  MethodSummary m;
  m.method = name;
  m.n = static_cast<int>(reps.size());
  m.n_failed = c.failed.count(name) ? c.failed.at(name) : 0;
  for (const Metric& metric : kMetrics) m.metrics[static_cast<std::size_t>(metric.id)] = metricCi(reps, metric.id);
  if (!ls.empty() && name != "ls") {
    VersusLs vs;
    for (const LsPaired& p : kVersusLs) vs.*p.field = pairedBy(reps, ls, [&](const Row& r) { return metricOf(r, p.metric); });
    m.vs_ls = vs;
  }
  for (std::size_t i = 0; i < parameters; ++i) m.parameters.push_back(parameterStatistics(reps, static_cast<Eigen::Index>(i)));
  m.rms_error_over_crb_max = worstOverCrb(m.parameters);
  return m;
}


// Holm over the cells, per method and metric compared with LS.
void adjustVersusLs(std::vector<CellSummary>& cells, std::size_t num_methods) {
  for (std::size_t k = 0; k < num_methods; ++k) {
    for (const LsPaired& p : kVersusLs) {
      std::vector<PairedComparison*> family;
      for (CellSummary& c : cells) {
        std::optional<VersusLs>& vs = c.methods[k].vs_ls;
        family.push_back(vs ? &((*vs).*p.field) : nullptr);
      }
      holmAdjustFamily(family);
    }
  }
}

// The paper cell with the same condition as an optimised cell (-1: none in this sweep).
int paperTwin(const std::vector<SweepCondition>& conds, std::size_t k) {
  const SweepCondition& o = conds[k];
  for (std::size_t i = 0; i < conds.size(); ++i) {
    const SweepCondition& p = conds[i];
    if (p.trajectories == "paper" && p.torque_noise_Nm == o.torque_noise_Nm && p.angle_noise_deg == o.angle_noise_deg &&
        p.quantisation_deg == o.quantisation_deg && p.vibration_level == o.vibration_level &&
        p.cylinder_mass_scale == o.cylinder_mass_scale && p.encoder_backlash_deg == o.encoder_backlash_deg) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

template <typename Get>
VersusPaper versusPaper(const Replicates& opt, const Replicates& pap, Get get) {
  return {pairedBy(opt, pap, get), meanOf(opt, get), meanOf(pap, get)};
}

// One method of an optimised cell against the same method in its paper twin (Holm not yet applied).
TrajectoryComparison compareWithTwin(const Cell& optimised, const Cell& paper, int paper_cell, const std::string& method, std::size_t parameters) {
  const Replicates& opt = repsOf(optimised, method);
  const Replicates& pap = repsOf(paper, method);
  TrajectoryComparison t;
  t.paper_cell = paper_cell;
  for (const PaperPaired& p : kVersusPaper) {
    t.*p.field = versusPaper(opt, pap, [&](const Row& r) { return metricOf(r, p.metric); });
  }
  for (std::size_t i = 0; i < parameters; ++i) {
    t.parameters.push_back(versusPaper(opt, pap, [i](const Row& r) { return std::abs(r.rel_best_fit[static_cast<Eigen::Index>(i)]); }));
  }
  return t;
}

// Holm per metric (each parameter's error is a metric) over the compared cells of method k.
void adjustVersusPaper(const std::vector<CellSummary*>& compared, std::size_t k) {
  const auto adjust = [&](auto pick) {
    std::vector<PairedComparison*> family;
    for (CellSummary* c : compared) family.push_back(&pick(*c->methods[k].vs_paper_trajectories).test);
    holmAdjustFamily(family);
  };
  for (const PaperPaired& p : kVersusPaper) adjust([&](TrajectoryComparison& t) -> VersusPaper& { return t.*p.field; });
  std::size_t most = 0;
  for (const CellSummary* c : compared) most = std::max(most, c->methods[k].vs_paper_trajectories->parameters.size());
  for (std::size_t i = 0; i < most; ++i) {
    std::vector<PairedComparison*> family;  // the cells that have parameter i
    for (CellSummary* c : compared) {
      std::vector<VersusPaper>& p = c->methods[k].vs_paper_trajectories->parameters;
      if (i < p.size()) family.push_back(&p[i].test);
    }
    holmAdjustFamily(family);
  }
}

// Every optimised cell against its paper twin (same condition, same seeds: the sweep's common
// random numbers), per method: the paired metrics and each parameter's |relative error|, with
// Holm over the compared cells per method and metric.
void compareTrajectories(const std::vector<SweepCondition>& conds, const std::map<int, Cell>& cells, std::vector<CellSummary>& out) {
  std::vector<CellSummary*> compared;
  std::vector<int> twins;
  for (CellSummary& c : out) {
    if (c.condition.trajectories != "optimised") continue;
    const int twin = paperTwin(conds, static_cast<std::size_t>(c.cell));
    if (twin < 0 || !cells.count(twin)) continue;
    compared.push_back(&c);
    twins.push_back(twin);
  }
  for (std::size_t j = 0; j < compared.size(); ++j) {
    for (MethodSummary& m : compared[j]->methods) {
      m.vs_paper_trajectories = compareWithTwin(cells.at(compared[j]->cell), cells.at(twins[j]), twins[j], m.method, compared[j]->parameters.size());
    }
  }
  if (compared.empty()) return;
  for (std::size_t k = 0; k < compared.front()->methods.size(); ++k) adjustVersusPaper(compared, k);
}

SweepSummary summarize(const SweepLayout& config, const std::vector<Row>& rows, const std::map<int, CellParameters>& parameters) {
  const std::vector<SweepCondition> conds = config.conditions();
  const std::map<int, Cell> cells = cellsOf(rows);
  SweepSummary s;
  s.layout = config;
  for (const auto& [cell, c] : cells) {
    CellSummary cs;
    cs.cell = cell;
    cs.condition = conds[static_cast<std::size_t>(cell)];
    if (const auto p = parameters.find(cell); p != parameters.end()) {
      cs.parameters = p->second.names;
      cs.truth = p->second.truth;
    }
    const Replicates& ls = repsOf(c, "ls");
    for (const std::string& m : config.method_names) cs.methods.push_back(summarizeMethod(c, m, ls, cs.parameters.size()));
    s.cells.push_back(std::move(cs));
  }
  adjustVersusLs(s.cells, config.method_names.size());
  compareTrajectories(conds, cells, s.cells);
  return s;
}

// ---- summary.json ----

nlohmann::json statisticsJson() {
  return {
      {"confidence_interval", "95 % Student t interval of the mean over seeds: mean -+ t(0.975, n-1) std / sqrt(n)"},
      {"paired_test", "Wilcoxon signed-rank vs ls over the same seeds, two-sided; exact for n <= 25 without ties, "
                      "else normal approximation with tie and continuity corrections; zero differences dropped"},
      {"p_holm", "Holm-Bonferroni adjusted over the sweep's cells, per method and metric"},
      {"mdd", "minimal detectable mean paired difference (method - ls) at 80 % power, alpha 0.05, paired t: "
              "(t(0.975, n-1) + t(0.8, n-1)) sd(diff) / sqrt(n)"},
      {"win_rate", "fraction of seeds where the method's value < ls's (ties count 1/2)"},
      {"vs_paper_trajectories", "an optimised-trajectories cell against its paper twin (same condition and seeds), per "
                                "method: Wilcoxon signed-rank, win_rate = share of seeds where optimised < paper, Holm "
                                "over the compared cells per method and metric (each parameter's error is a metric)"},
      {"torque_err", "||Y (x - x_bf)|| / ||Y x_bf|| per joint on the fixed validation states (ident::validationStates); a chain: "
                     "on the run's validation record, x_bf its truth"},
      {"abs_err_rms", "RMS over seeds of estimate - best fit truth (a parameter whose truth is zero has no relative error)"},
      {"crb_std", "noise-limited std of each parameter for the method's own regressor, processing and structure "
                  "(experiments::noiseStd); mean over the cell's seeds"},
      {"rms_error_over_crb", "RMS over seeds of (estimate - best fit truth) / crb_std of that seed"},
      {"coverage95", "share of seeds whose estimate -+ 1.96 crb_std (that seed's) held the best fit truth, with its Wilson 95 % "
                     "interval; mean_error_over_sigma: mean of (estimate - truth) / crb_std (the bias in those stds); "
                     "sd_over_mean_sigma: sample std of the errors / mean crb_std (1 when crb_std is the scatter)"},
      {"coverage95_reported", "the same with the standard errors the method reports (that seed's; segmental LS: identify's rule "
                              "stage by stage, ident/estimators/segmental_errors.hpp); n = 0 for a method that reports none"},
      {"norm_err_*_mxt_dominated", "||x - x*|| / ||x*||: dominated by Mxt and Myt, kept for comparison only"}};
}

nlohmann::json summaryJson(const stats::ConfidenceInterval& ci) {
  return {{"mean", jsonNumber(ci.mean)}, {"std", jsonNumber(ci.std)}, {"ci95_low", jsonNumber(ci.low)}, {"ci95_high", jsonNumber(ci.high)}};
}

nlohmann::json summaryJson(const PairedComparison& p) {
  return {{"n", p.n}, {"win_rate", jsonNumber(p.win_rate)}, {"p_value", jsonNumber(p.p_value)}, {"mdd", jsonNumber(p.mdd)},
          {"test", p.exact ? "wilcoxon exact" : "wilcoxon normal approximation"}, {"p_holm", jsonNumber(p.p_holm)}};
}

nlohmann::json summaryJson(const VersusPaper& v) {
  nlohmann::json j = summaryJson(v.test);
  j["optimised_mean"] = jsonNumber(v.optimised_mean);
  j["paper_mean"] = jsonNumber(v.paper_mean);
  return j;
}

nlohmann::json summaryJson(const ParameterStatistics& p) {
  return {{"rel_err", {{"mean", jsonNumber(p.rel_err.mean)}, {"ci95_low", jsonNumber(p.rel_err.low)}, {"ci95_high", jsonNumber(p.rel_err.high)}}},
          {"abs_rel_err_median", jsonNumber(p.abs_rel_err_median)},
          {"abs_rel_err_max", jsonNumber(p.abs_rel_err_max)},
          {"abs_err_rms", jsonNumber(p.abs_err_rms)},
          {"crb_std", jsonNumber(p.crb_std)},
          {"rms_error_over_crb", jsonNumber(p.rms_error_over_crb)},
          {"coverage95", coverageJson(p.coverage)},
          {"coverage95_reported", coverageJson(p.coverage_reported)}};
}

// An object of each parameter's entry, keyed by its name.
template <typename T>
nlohmann::json byParameter(const std::vector<std::string>& names, const std::vector<T>& entries) {
  nlohmann::json j;
  for (std::size_t i = 0; i < names.size() && i < entries.size(); ++i) j[names[i]] = summaryJson(entries[i]);
  return j;
}

nlohmann::json summaryJson(const TrajectoryComparison& t, const std::vector<std::string>& names) {
  nlohmann::json j;
  j["paper_cell"] = t.paper_cell;
  for (const PaperPaired& p : kVersusPaper) j[metricName(p.metric)] = summaryJson(t.*p.field);
  j["parameters"] = byParameter(names, t.parameters);
  return j;
}

nlohmann::json summaryJson(const MethodSummary& m, const std::vector<std::string>& names) {
  nlohmann::json j;
  j["n"] = m.n;
  j["n_failed"] = m.n_failed;
  for (const Metric& metric : kMetrics) j["metrics"][metric.name] = summaryJson(m.metric(metric.id));
  if (m.vs_ls) {
    for (const LsPaired& p : kVersusLs) j["vs_ls"][metricName(p.metric)] = summaryJson((*m.vs_ls).*p.field);
  }
  j["parameters"] = byParameter(names, m.parameters);
  j["rms_error_over_crb_max"] = jsonNumber(m.rms_error_over_crb_max);
  if (m.vs_paper_trajectories) j["vs_paper_trajectories"] = summaryJson(*m.vs_paper_trajectories, names);
  return j;
}

nlohmann::json summaryJson(const CellSummary& c) {
  nlohmann::json j;
  j["cell"] = c.cell;
  j["condition"] = toJson(c.condition);
  if (!c.truth.empty()) j["base_parameters"] = {{"names", c.parameters}, {"truth", c.truth}};
  for (const MethodSummary& m : c.methods) j["methods"][m.method] = summaryJson(m, c.parameters);
  return j;
}

// ---- summary.csv and summary.md ----

void writeSummaryCsv(const SweepSummary& s, const std::string& path) {
  std::vector<const std::vector<std::string>*> lists;
  for (const CellSummary& c : s.cells) lists.push_back(&c.parameters);
  const std::vector<std::string> names = allNames(lists);
  core::writeFileAtomically(path, [&](std::ostream& out) {
    out << "cell," << kConditionCsvHeader << ",method,n,n_failed";
    for (const Metric& m : kMetrics) {
      for (const char* f : {"mean", "std", "ci95_low", "ci95_high"}) out << ',' << m.name << '_' << f;
    }
    for (const LsPaired& p : kVersusLs) {
      const char* n = metricName(p.metric);
      out << ",win_rate_vs_ls_" << n << ",p_wilcoxon_vs_ls_" << n << ",p_holm_vs_ls_" << n << ",mdd_vs_ls_" << n;
    }
    for (const std::string& n : names) out << ',' << csvField("rms_error_over_crb_" + n);
    out << ",rms_error_over_crb_max";
    for (const std::string& n : names) out << ',' << csvField("coverage95_" + n);
    for (const PaperPaired& p : kVersusPaper) {
      out << ",win_rate_vs_paper_trajectories_" << metricName(p.metric) << ",p_holm_vs_paper_trajectories_" << metricName(p.metric);
    }
    out << "\n";
    for (const CellSummary& c : s.cells) {
      for (const MethodSummary& m : c.methods) {
        out << c.cell << ',' << conditionCsv(c.condition) << ',' << m.method << ',' << m.n << ',' << m.n_failed;
        for (const stats::ConfidenceInterval& ci : m.metrics) {
          out << ',' << csvNumber(ci.mean) << ',' << csvNumber(ci.std) << ',' << csvNumber(ci.low) << ',' << csvNumber(ci.high);
        }
        for (const LsPaired& p : kVersusLs) {
          if (m.vs_ls) {
            const PairedComparison& q = (*m.vs_ls).*p.field;
            out << ',' << csvNumber(q.win_rate) << ',' << csvNumber(q.p_value) << ',' << csvNumber(q.p_holm) << ',' << csvNumber(q.mdd);
          } else {
            out << ",,,,";
          }
        }
        // A parameter this cell does not have (a chain's base-motion ones on a still base): empty.
        const std::vector<std::size_t> at = positions(names, c.parameters);
        for (const std::size_t i : at) out << ',' << csvNumber(i < m.parameters.size() ? m.parameters[i].rms_error_over_crb : kNaN);
        out << ',' << csvNumber(m.rms_error_over_crb_max);
        for (const std::size_t i : at) out << ',' << csvNumber(i < m.parameters.size() ? m.parameters[i].coverage.share : kNaN);
        for (const PaperPaired& p : kVersusPaper) {
          if (m.vs_paper_trajectories) {
            const PairedComparison& q = ((*m.vs_paper_trajectories).*p.field).test;
            out << ',' << csvNumber(q.win_rate) << ',' << csvNumber(q.p_holm);
          } else {
            out << ",,";
          }
        }
        out << '\n';
      }
    }
  });
}

std::string ciText(const stats::ConfidenceInterval& ci, double scale, int decimals) {
  if (!std::isfinite(ci.mean)) return "-";
  std::string s = fixed(scale * ci.mean, decimals);
  if (std::isfinite(ci.low)) s += " [" + fixed(scale * ci.low, decimals) + ", " + fixed(scale * ci.high, decimals) + "]";
  return s;
}

// "P -> O (win rate, Holm p)" of one paired trajectory comparison, in % when scale is 100.
std::string trajectoryPairText(const VersusPaper& p, double scale, int decimals) {
  if (!std::isfinite(p.optimised_mean) || !std::isfinite(p.paper_mean)) return "-";
  return fixed(scale * p.paper_mean, decimals) + " -> " + fixed(scale * p.optimised_mean, decimals) + " (" +
         fixed(p.test.win_rate, 2) + ", p = " + fmt(p.test.p_holm, 2) + ")";
}

// A section's heading: the condition without the torque noise (the tables' columns); a chain has no cylinder.
std::string sectionKey(const SweepCondition& k, bool chain) {
  return (chain ? std::string() : "cylinder mass scale " + fmt(k.cylinder_mass_scale) + ", ") + "vibration level " + fmt(k.vibration_level) + ", angle noise " +
         fmt(k.angle_noise_deg) + " deg, quantisation " + fmt(k.quantisation_deg) + " deg" +
         (k.encoder_backlash_deg > 0.0 ? ", encoder backlash " + fmt(k.encoder_backlash_deg) + " deg" : std::string());
}

using Section = std::pair<std::string, std::vector<const CellSummary*>>;  // heading, its cells

// The cells grouped by heading, in the order the headings first appear.
template <typename Key>
std::vector<Section> sectionsOf(const std::vector<const CellSummary*>& cells, Key key) {
  std::vector<Section> sections;
  for (const CellSummary* c : cells) {
    const std::string k = key(*c);
    auto it = std::find_if(sections.begin(), sections.end(), [&](const Section& s) { return s.first == k; });
    if (it == sections.end()) it = sections.insert(sections.end(), Section{k, {}});
    it->second.push_back(c);
  }
  return sections;
}

// A table's header: `first`, then one column per cell by its torque noise.
std::vector<std::string> noiseHeader(const std::string& first, const std::vector<const CellSummary*>& cs) {
  std::vector<std::string> header{first};
  for (const CellSummary* c : cs) header.push_back("tau noise " + fmt(c->condition.torque_noise_Nm) + " N m");
  return header;
}

const char* kTrajectoryMetricTitles[] = {"Torque-space error (%)", "Median per-parameter |error| (%)", "Worst per-parameter |error| (%)"};

// One trajectory-comparison section: methods x torque noise per metric, then per parameter for LS and RLS-PSO.
void writeTrajectorySection(std::ostream& md, const std::vector<std::string>& methods, const Section& section) {
  const std::vector<const CellSummary*>& cs = section.second;
  const std::vector<std::string> header = noiseHeader("method", cs);
  md << "\n## " << section.first << "\n";
  for (int k = 0; k < 3; ++k) {
    md << "\n" << kTrajectoryMetricTitles[k] << "\n\n";
    TextTable t(header);
    for (const std::string& v : methods) {
      std::vector<std::string> row{v};
      for (const CellSummary* c : cs) {
        row.push_back(trajectoryPairText((*c->method(v).vs_paper_trajectories).*kVersusPaper[k].field, 100.0, 2));
      }
      t.addRow(row);
    }
    t.printMarkdown(md);
  }
  for (const char* method : {"ls", "rls-pso"}) {
    if (cs.front()->find(method) == nullptr) continue;
    md << "\n" << method << ": per-parameter |error| (%)\n\n";
    TextTable t(noiseHeader("param", cs));
    for (std::size_t i = 0; i < cs.front()->parameters.size(); ++i) {
      std::vector<std::string> row{cs.front()->parameters[i]};
      for (const CellSummary* c : cs) {
        const std::vector<VersusPaper>& p = c->method(method).vs_paper_trajectories->parameters;
        row.push_back(i < p.size() ? trajectoryPairText(p[i], 100.0, 2) : "-");
      }
      t.addRow(row);
    }
    t.printMarkdown(md);
  }
}

// The trajectory axis: each optimised cell against its paper twin, grouped like the sections.
void writeTrajectoryComparisonMd(const SweepSummary& s, std::ostream& md) {
  std::vector<const CellSummary*> compared;
  for (const CellSummary& c : s.cells) {
    if (!c.methods.empty() && c.methods.front().vs_paper_trajectories) compared.push_back(&c);
  }
  if (compared.empty()) return;
  md << "\n# Optimised vs the paper's identification trajectories\n\nEach optimised cell against the paper cell with the "
        "same condition and the same seeds (validation on trajectories 2 and 4 in both): paper -> optimised mean over seeds "
        "(share of seeds where optimised is better, Wilcoxon signed-rank p, Holm-adjusted over the compared cells per method "
        "and metric).\n";
  for (const Section& section : sectionsOf(compared, [&](const CellSummary& c) { return sectionKey(c.condition, s.layout.chain); })) {
    writeTrajectorySection(md, s.layout.method_names, section);
  }
}

enum class CellTable { kTorque, kParams, kCrb };

// A method's entry in a cell of one of the section's first three tables.
std::string cellText(const MethodSummary& m, CellTable what) {
  if (what == CellTable::kTorque) return ciText(m.metric(SweepMetric::kTorqueErrMean), 100.0, 2);
  if (what == CellTable::kParams) {
    const double med = m.metric(SweepMetric::kMedianAbsRelErr).mean, worst = m.metric(SweepMetric::kMaxAbsRelErr).mean;
    return std::isfinite(med) ? fixed(100.0 * med, 1) + " (" + fixed(100.0 * worst, 1) + ")" : "-";
  }
  const double r = m.rms_error_over_crb_max;
  return std::isfinite(r) ? fmt(r, 3) : "-";
}

// Methods (rows) x torque noise (columns): the torque-space error, the median and worst
// per-parameter error, the worst error in units of the method's CRB.
void writeMethodTables(std::ostream& md, const std::vector<std::string>& methods, const std::vector<const CellSummary*>& cs) {
  for (const auto& [what, title] : {std::pair{CellTable::kTorque, "Torque-space error (%)"},
                                    std::pair{CellTable::kParams, "Per-parameter |error| (%): median (worst)"},
                                    std::pair{CellTable::kCrb, "Worst RMS error / CRB"}}) {
    const CellTable table = what;  // a structured binding cannot be captured (C++17)
    const bool any = std::any_of(cs.begin(), cs.end(), [&](const CellSummary* c) {
      return std::any_of(c->methods.begin(), c->methods.end(), [&](const MethodSummary& m) { return cellText(m, table) != "-"; });
    });
    if (!any) continue;  // a chain's runs give no CRB
    md << "\n" << title << "\n\n";
    TextTable t(noiseHeader("method", cs));
    for (const std::string& v : methods) {
      std::vector<std::string> row{v};
      for (const CellSummary* c : cs) row.push_back(cellText(c->method(v), what));
      t.addRow(row);
    }
    t.printMarkdown(md);
  }
}

// Every method against LS on the torque-space error: is it closer to the truth, significantly?
void writeVersusLsTable(std::ostream& md, const std::vector<std::string>& methods, const std::vector<const CellSummary*>& cs) {
  TextTable t(noiseHeader("method", cs));
  bool any = false;
  for (const std::string& v : methods) {
    std::vector<std::string> row{v};
    bool have = false;
    for (const CellSummary* c : cs) {
      const MethodSummary& m = c->method(v);
      if (!m.vs_ls) {
        row.push_back("-");
        continue;
      }
      have = true;
      const PairedComparison& p = m.vs_ls->torque_err_mean;
      row.push_back(fixed(p.win_rate, 2) + ", p = " + fmt(p.p_holm, 3) + ", n = " + core::toText(static_cast<long>(p.n)));
    }
    if (have) t.addRow(row);
    any = any || have;
  }
  if (any) {
    md << "\nVs LS on the torque-space error (share of seeds where the method is closer to the truth, Holm-adjusted p, "
          "seeds where both were usable)\n\n";
    t.printMarkdown(md);
  }
}

// Per cell: how often each method's nominal 95 % intervals held the truth, per parameter, and the
// verdict naming every parameter short of kCoverageShortfall: with -+ 1.96 CRB std, then with
// -+ 1.96 of the standard errors a method reports. A method with no interval for any parameter is
// left out, and a table with none at all (a chain's runs give no CRB; a noise-free cell's) too.
void writeCoverageTable(std::ostream& md, const std::vector<std::string>& methods, const CellSummary& c, stats::Coverage ParameterStatistics::*which,
                        const std::string& sigma, const std::string& unit) {
  const std::vector<std::string>& names = c.parameters;
  std::vector<std::string> header{"method"};
  header.insert(header.end(), names.begin(), names.end());
  TextTable t(header);
  std::string verdict;
  int shown = 0;
  for (const std::string& v : methods) {
    const MethodSummary& m = c.method(v);
    std::vector<std::string> row{v};
    std::vector<stats::Coverage> coverage;
    for (const ParameterStatistics& p : m.parameters) {
      const stats::Coverage& k = p.*which;
      row.push_back(k.n ? fixed(100.0 * k.share, 0) : "-");
      coverage.push_back(k);
    }
    if (std::all_of(coverage.begin(), coverage.end(), [](const stats::Coverage& k) { return k.n == 0; })) continue;
    t.addRow(row);
    ++shown;
    if (const std::string short_of = coverageShortfall(names, coverage); !short_of.empty()) verdict += "- " + v + ": " + short_of + "\n";
  }
  if (shown == 0) return;
  md << "\nCoverage: seeds (%) whose estimate -+ 1.96 " << sigma << " held the truth, torque noise " << fmt(c.condition.torque_noise_Nm, 4)
     << " N m (nominal 95 %)\n\n";
  t.printMarkdown(md);
  md << "\n" << (verdict.empty() ? "Every method covers every parameter in at least " + fixed(100.0 * kCoverageShortfall, 0) + " % of the seeds.\n"
                                  : "Short of " + fixed(100.0 * kCoverageShortfall, 0) + " % (share [Wilson 95 %], the mean error and the scatter "
                                    "in " + unit + "):\n" + verdict);
}

void writeCoverageTables(std::ostream& md, const std::vector<std::string>& methods, const std::vector<const CellSummary*>& cs) {
  for (const CellSummary* c : cs) {
    writeCoverageTable(md, methods, *c, &ParameterStatistics::coverage, "CRB std", "CRB stds");
    writeCoverageTable(md, methods, *c, &ParameterStatistics::coverage_reported, "reported standard errors", "reported standard errors");
  }
}

// Per cell: each parameter's median |relative error| per method (the RMS of its absolute error
// where its truth is zero: a chain's parameter that the combination zeroes).
void writeParameterTables(std::ostream& md, const std::vector<std::string>& methods, const std::vector<const CellSummary*>& cs) {
  for (const CellSummary* c : cs) {
    md << "\nPer-parameter |error| (%), median over the seeds, torque noise " << fmt(c->condition.torque_noise_Nm, 4) << " N m\n\n";
    std::vector<std::string> header{"parameter"};
    header.insert(header.end(), methods.begin(), methods.end());
    TextTable t(header);
    for (std::size_t i = 0; i < c->parameters.size(); ++i) {
      std::vector<std::string> row{c->parameters[i]};
      for (const std::string& v : methods) {
        const ParameterStatistics& p = c->method(v).parameters[i];
        row.push_back(std::isfinite(p.abs_rel_err_median) ? fixed(100.0 * p.abs_rel_err_median, 2)
                                                          : std::isfinite(p.abs_err_rms) ? fmt(p.abs_err_rms, 3) + " abs" : "-");
      }
      t.addRow(row);
    }
    t.printMarkdown(md);
  }
}

// RLS-PSO vs LS on the paired metrics, when the sweep compared them in any of the section's cells.
void writeRlsPsoTable(std::ostream& md, const std::vector<const CellSummary*>& cs) {
  bool have_pair = false;
  for (const CellSummary* c : cs) have_pair = have_pair || (c->find("rls-pso") != nullptr && c->find("rls-pso")->vs_ls);
  if (!have_pair) return;
  md << "\nRLS-PSO vs LS (win rate, Holm-adjusted p, MDD)\n\n";
  TextTable t(noiseHeader("metric", cs));
  for (const LsPaired& q : kVersusLs) {
    std::vector<std::string> row{metricName(q.metric)};
    for (const CellSummary* c : cs) {
      const PairedComparison& p = (*c->method("rls-pso").vs_ls).*q.field;
      const double scale = q.metric == SweepMetric::kValRms ? 1.0 : 100.0;
      row.push_back(fixed(p.win_rate, 2) + ", p = " + fmt(p.p_holm, 3) + ", MDD " + fmt(scale * p.mdd, 3) +
                    (scale == 100.0 ? " %" : " N m"));
    }
    t.addRow(row);
  }
  t.printMarkdown(md);
}

// One section per (trajectories, cylinder, vibration, angle noise, quantisation): methods (rows) x
// torque noise (columns) for the torque-space error, the median and worst per-parameter error, the
// worst error in units of the method's CRB, every method vs LS, and RLS-PSO vs LS.
void writeSummaryMd(const SweepSummary& s, const std::string& path) {
  core::writeFileAtomically(path, [&](std::ostream& md) {
    if (s.layout.chain) {
      const nlohmann::json& sw = s.layout.resolved.at("sweep");
      md << "# Sweep summary: --model " << sw.at("model").get<std::string>() << "\n\nMean over seeds [95 % Student-t CI]. Each run: "
         << sw.at("design").get<std::string>() << ". Torque-space error: ||Wv (x - x*)|| / ||Wv x*|| on the validation record, x* "
            "the simulation's truth, mean over the joints, in %. Per-parameter error: median (worst) over the base parameters "
            "with a non-zero truth of |x_i - x*_i| / |x*_i|, in %. Paired comparison: Wilcoxon signed-rank vs LS over the same "
            "seeds, Holm-adjusted over the sweep's cells; MDD = minimal detectable difference at 80 % power. No figures: "
            "runs.csv has every run.\n";
    } else {
      md << "# Sweep summary\n\nMean over seeds [95 % Student-t CI]. Torque-space error: ||Y (x - x_bf)|| / ||Y x_bf|| on the "
            "fixed validation states, mean of hip and knee, in %. Per-parameter error: median (worst) over the 10 parameters "
            "of |x_i - x_bf,i| / |x_bf,i|, in %. Error/CRB: the largest over parameters of RMS(error) / (the method's "
            "noise-limited std). Paired comparison: Wilcoxon signed-rank vs LS over the same seeds, Holm-adjusted over the "
            "sweep's cells; MDD = minimal detectable difference at 80 % power.\n";
    }
    std::vector<const CellSummary*> cells;
    for (const CellSummary& c : s.cells) cells.push_back(&c);
    const auto key = [&](const CellSummary& c) {
      const std::string& t = c.condition.trajectories;
      return (t == "optimised" ? std::string("optimised trajectories, ") : t == "paper" ? std::string("paper's trajectories, ") : t + " motion, ") +
             sectionKey(c.condition, s.layout.chain);
    };
    for (const auto& [heading, cs] : sectionsOf(cells, key)) {
      md << "\n## " << heading << "\n";
      writeMethodTables(md, s.layout.method_names, cs);
      writeVersusLsTable(md, s.layout.method_names, cs);
      writeRlsPsoTable(md, cs);
      writeCoverageTables(md, s.layout.method_names, cs);
      writeParameterTables(md, s.layout.method_names, cs);
    }
    writeTrajectoryComparisonMd(s, md);
  });
}

}  // namespace

const char* metricName(SweepMetric m) { return kMetrics[static_cast<std::size_t>(m)].name; }

const MethodSummary* CellSummary::find(const std::string& method) const {
  for (const MethodSummary& m : methods) {
    if (m.method == method) return &m;
  }
  return nullptr;
}

const MethodSummary& CellSummary::method(const std::string& method) const {
  if (const MethodSummary* m = find(method)) return *m;
  throw std::out_of_range("sweep summary: cell " + core::toText(cell) + " has no method '" + method + "'");
}

SweepLayout layoutOf(const SweepConfig& c) {
  return {c.conditions(), c.seeds, c.toJson(), c.isChain(), c.methodNames()};
}

SweepLayout layoutFromJson(const nlohmann::json& resolved) {
  try {
    SweepConfig c;
    const nlohmann::json& g = resolved.at("grid");
    c.torque_noise_Nm = g.at("torque_noise_Nm").get<std::vector<double>>();
    c.angle_noise_deg = g.at("angle_noise_deg").get<std::vector<double>>();
    c.quantisation_deg = g.at("quantisation_deg").get<std::vector<double>>();
    c.vibration_level = g.at("vibration_level").get<std::vector<double>>();
    c.cylinder_mass_scale = g.at("cylinder_mass_scale").get<std::vector<double>>();
    // Written since the axis exists; a folder from before it had none (no play).
    if (g.contains("encoder_backlash_deg")) c.encoder_backlash_deg = g.at("encoder_backlash_deg").get<std::vector<double>>();
    if (g.contains("trajectories")) c.trajectories = g.at("trajectories").get<std::vector<std::string>>();
    const std::vector<std::string> names = resolved.at("sweep").at("methods").get<std::vector<std::string>>();
    const bool chain = resolved.at("sweep").contains("model");
    if (!chain) {
      for (const std::string& m : names) parseVariant(m);  // a malformed folder's unknown method fails here
    }
    return {c.conditions(), resolved.at("sweep").at("seeds").get<int>(), resolved, chain, names};
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("malformed sweep configuration (config.json): ") + e.what());
  }
}

SweepSummary summarizeSweep(const SweepLayout& config, const std::vector<nlohmann::json>& jobs) {
  return summarize(config, rowsOf(config, jobs), parametersOf(config, jobs));
}

nlohmann::json toJson(const SweepSummary& s) {
  nlohmann::json out;
  out["tool"] = toolJson();
  out["config"] = s.layout.resolved;
  out["statistics"] = statisticsJson();
  nlohmann::json conditions = nlohmann::json::array();
  for (const CellSummary& c : s.cells) conditions.push_back(summaryJson(c));
  out["conditions"] = conditions;
  return out;
}

void writeSweepTables(const SweepLayout& config, const std::vector<nlohmann::json>& jobs, const std::string& dir) {
  const std::vector<Row> rows = rowsOf(config, jobs);
  const std::map<int, CellParameters> parameters = parametersOf(config, jobs);
  writeRunsCsv(config, rows, parameters, dir + "/runs.csv");
  const SweepSummary s = summarize(config, rows, parameters);
  writeJsonFile(dir + "/summary.json", toJson(s));
  testKillPoint("sweep-tables");
  writeSummaryCsv(s, dir + "/summary.csv");
  writeSummaryMd(s, dir + "/summary.md");
}

}  // namespace exoid::experiments
