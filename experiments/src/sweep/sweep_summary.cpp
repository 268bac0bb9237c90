#include "exoid/experiments/sweep/sweep_summary.hpp"

#include "exoid/core/format.hpp"
#include "exoid/experiments/sweep/fault_injection.hpp"
#include "exoid/experiments/protocol/identification.hpp"
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

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
using ident::kNumParams;

// Scores of one (job, method), recomputed from the stored raw numbers.
struct Row {
  int cell = 0, replicate = 0;
  std::uint64_t seed = 0;
  std::string method, status, message;
  bool ok = false;
  double err_rigid = kNaN, err_best_fit = kNaN;  // norms: Mxt-dominated, kept under that name
  Eigen::VectorXd rel_best_fit = Eigen::VectorXd::Constant(kNumParams, kNaN);
  Eigen::VectorXd rel_rigid = Eigen::VectorXd::Constant(kNumParams, kNaN);
  Eigen::VectorXd abs_best_fit = Eigen::VectorXd::Constant(kNumParams, kNaN);
  Eigen::VectorXd crb = Eigen::VectorXd::Constant(kNumParams, kNaN);  // this method's noise std
  Eigen::VectorXd z = Eigen::VectorXd::Constant(kNumParams, kNaN);    // abs_best_fit / crb
  double ts_hip = kNaN, ts_knee = kNaN;                                // torque-space vs best fit
  double gap_box = kNaN, gap_free = kNaN;                              // worst stage
  double median_abs_rel = kNaN, max_abs_rel = kNaN;
  double plausible = kNaN;  // 1 when no physical condition is violated
  double val[6] = {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};  // knee mean/std/rms, hip mean/std/rms
  double wall_time_s = kNaN;
};

Eigen::VectorXd vec(const nlohmann::json& j) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(j.size()));
  for (std::size_t i = 0; i < j.size(); ++i) v[static_cast<Eigen::Index>(i)] = j[i].get<double>();
  return v;
}

double median(std::vector<double> v) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const std::size_t h = v.size() / 2;
  return v.size() % 2 ? v[h] : 0.5 * (v[h - 1] + v[h]);
}

// The per-method scores of a job record: CRB, torque-space errors, optimality gaps.
void readScores(const nlohmann::json& m, Row& r) {
  r.crb = vec(m.at("crb_std"));
  r.plausible = m.at("implausible").empty() ? 1.0 : 0.0;
  for (int i = 0; i < kNumParams; ++i) r.z[i] = r.crb[i] > 0.0 ? r.abs_best_fit[i] / r.crb[i] : kNaN;
  r.ts_hip = m.at("torque_space").at("best_fit").at("hip").get<double>();
  r.ts_knee = m.at("torque_space").at("best_fit").at("knee").get<double>();
  for (const auto& [stage, g] : m.at("optimality_gaps").items()) {
    if (g.contains("box")) r.gap_box = std::isnan(r.gap_box) ? g["box"].get<double>() : std::max(r.gap_box, g["box"].get<double>());
    if (g.contains("unconstrained")) {
      r.gap_free = std::isnan(r.gap_free) ? g["unconstrained"].get<double>() : std::max(r.gap_free, g["unconstrained"].get<double>());
    }
  }
  std::vector<double> a(r.rel_best_fit.data(), r.rel_best_fit.data() + kNumParams);
  for (double& x : a) x = std::abs(x);
  r.max_abs_rel = *std::max_element(a.begin(), a.end());
  r.median_abs_rel = median(a);
}

std::vector<Row> rowsOf(const SweepLayout& config, const std::vector<nlohmann::json>& jobs) {
  std::vector<Row> rows;
  for (const nlohmann::json& job : jobs) {
    Row base;
    base.cell = job.at("cell").get<int>();
    base.replicate = job.at("replicate").get<int>();
    base.seed = job.at("seed").get<std::uint64_t>();
    if (job.at("status") != "ok") {
      for (Variant v : config.methods) {
        Row r = base;
        r.method = toString(v);
        r.status = "error";
        r.message = job.at("message").get<std::string>();
        rows.push_back(r);
      }
      continue;
    }
    const Eigen::VectorXd rigid = vec(job.at("truth").at("rigid")), best = vec(job.at("truth").at("best_fit"));
    for (const nlohmann::json& m : job.at("methods")) {
      Row r = base;
      r.method = m.at("method").get<std::string>();
      r.status = m.at("status").get<std::string>();
      r.message = m.at("message").get<std::string>();
      r.ok = r.status == "ok";
      const Eigen::VectorXd x = vec(m.at("x"));
      const ident::ParamError eb = ident::paramError(x, best), er = ident::paramError(x, rigid);
      r.err_best_fit = eb.norm_rel;
      r.err_rigid = er.norm_rel;
      r.rel_best_fit = eb.rel;
      r.rel_rigid = er.rel;
      r.abs_best_fit = eb.abs;
      readScores(m, r);
      int k = 0;
      for (const char* joint : {"knee_validation", "hip_validation"}) {
        for (const char* f : {"mean_abs", "std_abs", "rms"}) r.val[k++] = m.at(joint).at(f).get<double>();
      }
      r.wall_time_s = m.at("wall_time_s").get<double>();
      rows.push_back(r);
    }
  }
  return rows;
}

std::string num(double v) { return std::isfinite(v) ? fmt(v, 10) : std::string(); }
nlohmann::json jnum(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

std::string csvQuote(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string conditionCsv(const SweepCondition& c) {
  return num(c.torque_noise_Nm) + "," + num(c.angle_noise_deg) + "," + num(c.quantisation_deg) + "," +
         num(c.vibration_level) + "," + num(c.cylinder_mass_scale) + "," + c.trajectories;
}
const char* kConditionHeader = "torque_noise_Nm,angle_noise_deg,quantisation_deg,vibration_level,cylinder_mass_scale,trajectories";

// The summary metrics: name and how to read it from a row.
struct Metric {
  const char* name;
  double (*get)(const Row&);
};
const Metric kMetrics[] = {
    {"torque_err_hip", [](const Row& r) { return r.ts_hip; }},
    {"torque_err_knee", [](const Row& r) { return r.ts_knee; }},
    {"torque_err_mean", [](const Row& r) { return 0.5 * (r.ts_hip + r.ts_knee); }},
    {"median_abs_rel_err", [](const Row& r) { return r.median_abs_rel; }},
    {"max_abs_rel_err", [](const Row& r) { return r.max_abs_rel; }},
    {"norm_err_best_fit_mxt_dominated", [](const Row& r) { return r.err_best_fit; }},
    {"norm_err_rigid_mxt_dominated", [](const Row& r) { return r.err_rigid; }},
    {"gap_box_max", [](const Row& r) { return r.gap_box; }},
    {"plausible_rate", [](const Row& r) { return r.plausible; }},
    {"gap_unconstrained_max", [](const Row& r) { return r.gap_free; }},
    {"knee_val_mean_abs", [](const Row& r) { return r.val[0]; }},
    {"knee_val_rms", [](const Row& r) { return r.val[2]; }},
    {"hip_val_mean_abs", [](const Row& r) { return r.val[3]; }},
    {"hip_val_rms", [](const Row& r) { return r.val[5]; }},
    {"val_rms", [](const Row& r) { return 0.5 * (r.val[2] + r.val[5]); }},
};
// Paired comparisons against LS run on these.
const char* kPaired[] = {"torque_err_mean", "val_rms"};

double metricOf(const Row& r, const std::string& name) {
  for (const Metric& m : kMetrics) {
    if (name == m.name) return m.get(r);
  }
  return kNaN;
}

struct Cell {
  std::map<std::string, std::map<int, const Row*>> by_method;  // method -> replicate -> row (ok only)
  std::map<std::string, int> failed;
};

void writeRunsCsv(const SweepLayout& config, const std::vector<Row>& rows, const std::string& path) {
  const std::vector<SweepCondition> conds = config.conditions();
  core::writeFileAtomically(path, [&](std::ostream& out) {
    out << "cell,replicate," << kConditionHeader
        << ",seed,method,status,torque_err_hip,torque_err_knee,median_abs_rel_err,max_abs_rel_err,"
           "norm_err_rigid_mxt_dominated,norm_err_best_fit_mxt_dominated,gap_box_max,gap_unconstrained_max,plausible";
    for (const char* prefix : {"rel_err_", "rel_err_rigid_", "err_over_crb_", "crb_std_"}) {
      for (int i = 0; i < kNumParams; ++i) out << ',' << prefix << ident::paramName(i);
    }
    out << ",knee_val_mean_abs,knee_val_std_abs,knee_val_rms,hip_val_mean_abs,hip_val_std_abs,hip_val_rms,message,wall_time_s\n";
    for (const Row& r : rows) {
      out << r.cell << ',' << r.replicate << ',' << conditionCsv(conds[static_cast<std::size_t>(r.cell)]) << ',' << r.seed << ','
          << r.method << ',' << r.status << ',' << num(r.ts_hip) << ',' << num(r.ts_knee) << ',' << num(r.median_abs_rel)
          << ',' << num(r.max_abs_rel) << ',' << num(r.err_rigid) << ',' << num(r.err_best_fit) << ',' << num(r.gap_box) << ','
          << num(r.gap_free) << ',' << num(r.plausible);
      for (const Eigen::VectorXd* v : {&r.rel_best_fit, &r.rel_rigid, &r.z, &r.crb}) {
        for (int i = 0; i < kNumParams; ++i) out << ',' << num((*v)[i]);
      }
      for (double v : r.val) out << ',' << num(v);
      out << ',' << csvQuote(r.message) << ',' << num(r.wall_time_s) << '\n';
    }
  });
}

struct Paired {
  int n = 0;
  double win_rate = kNaN, p_value = kNaN, median_diff = kNaN;
  double mdd = kNaN;  // minimal detectable mean difference, 80 % power, alpha 0.05
  bool exact = false;
};
Paired pairedValues(const std::vector<double>& a, const std::vector<double>& b);
// `m` against `ref` over the replicates both have, on a metric of a row.
template <typename Get>
Paired pairedBy(const std::map<int, const Row*>& m, const std::map<int, const Row*>& ref, Get get) {
  std::vector<double> a, b;
  for (const auto& [rep, row] : m) {
    const auto it = ref.find(rep);
    if (it == ref.end()) continue;
    a.push_back(get(*row));
    b.push_back(get(*it->second));
  }
  return pairedValues(a, b);
}
Paired paired(const std::map<int, const Row*>& m, const std::map<int, const Row*>& ls, const std::string& metric) {
  return pairedBy(m, ls, [&](const Row& r) { return metricOf(r, metric); });
}
Paired pairedValues(const std::vector<double>& a, const std::vector<double>& b) {
  Paired p;
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

}  // namespace

SweepLayout layoutOf(const SweepConfig& c) { return {c.conditions(), c.methods, c.seeds, c.toJson()}; }

SweepLayout layoutFromJson(const nlohmann::json& resolved) {
  try {
    SweepConfig c;
    const nlohmann::json& g = resolved.at("grid");
    c.torque_noise_Nm = g.at("torque_noise_Nm").get<std::vector<double>>();
    c.angle_noise_deg = g.at("angle_noise_deg").get<std::vector<double>>();
    c.quantisation_deg = g.at("quantisation_deg").get<std::vector<double>>();
    c.vibration_level = g.at("vibration_level").get<std::vector<double>>();
    c.cylinder_mass_scale = g.at("cylinder_mass_scale").get<std::vector<double>>();
    if (g.contains("trajectories")) c.trajectories = g.at("trajectories").get<std::vector<std::string>>();
    c.methods.clear();
    for (const auto& m : resolved.at("sweep").at("methods")) c.methods.push_back(parseVariant(m.get<std::string>()));
    return {c.conditions(), c.methods, resolved.at("sweep").at("seeds").get<int>(), resolved};
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("malformed sweep configuration (config.json): ") + e.what());
  }
}

namespace {

// Per parameter over a method's seeds: signed relative error (mean, CI), median and worst |rel|,
// mean noise std (CRB) and RMS of error / CRB.
nlohmann::json parameterJson(const std::map<int, const Row*>& reps) {
  nlohmann::json out;
  for (int i = 0; i < kNumParams; ++i) {
    std::vector<double> rel, abs_rel, crb;
    double z2 = 0.0;
    int zn = 0;
    for (const auto& [rep, row] : reps) {
      rel.push_back(row->rel_best_fit[i]);
      abs_rel.push_back(std::abs(row->rel_best_fit[i]));
      if (std::isfinite(row->crb[i])) crb.push_back(row->crb[i]);
      if (std::isfinite(row->z[i])) {
        z2 += row->z[i] * row->z[i];
        ++zn;
      }
    }
    const stats::ConfidenceInterval ci = stats::meanCi(rel);
    out[std::string(ident::paramName(i))] = {
        {"rel_err", {{"mean", jnum(ci.mean)}, {"ci95_low", jnum(ci.low)}, {"ci95_high", jnum(ci.high)}}},
        {"abs_rel_err_median", jnum(median(abs_rel))},
        {"abs_rel_err_max", jnum(abs_rel.empty() ? kNaN : *std::max_element(abs_rel.begin(), abs_rel.end()))},
        {"crb_std", jnum(stats::mean(crb))},
        {"rms_error_over_crb", jnum(zn ? std::sqrt(z2 / zn) : kNaN)}};
  }
  return out;
}

const std::map<int, const Row*>& repsOf(const Cell& c, const std::string& method) {
  static const std::map<int, const Row*> empty;
  const auto it = c.by_method.find(method);
  return it == c.by_method.end() ? empty : it->second;
}

// The paper cell with the same condition as an optimised cell (-1: none in this sweep).
int paperTwin(const std::vector<SweepCondition>& conds, std::size_t k) {
  const SweepCondition& o = conds[k];
  for (std::size_t i = 0; i < conds.size(); ++i) {
    const SweepCondition& p = conds[i];
    if (p.trajectories == "paper" && p.torque_noise_Nm == o.torque_noise_Nm && p.angle_noise_deg == o.angle_noise_deg &&
        p.quantisation_deg == o.quantisation_deg && p.vibration_level == o.vibration_level &&
        p.cylinder_mass_scale == o.cylinder_mass_scale) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

nlohmann::json pairedJson(const Paired& p, double optimised_mean, double paper_mean) {
  return {{"n", p.n}, {"win_rate", jnum(p.win_rate)}, {"p_value", jnum(p.p_value)}, {"mdd", jnum(p.mdd)},
          {"optimised_mean", jnum(optimised_mean)}, {"paper_mean", jnum(paper_mean)},
          {"test", p.exact ? "wilcoxon exact" : "wilcoxon normal approximation"}};
}

// Paired metrics of the trajectory comparison.
const char* kTrajectoryPaired[] = {"torque_err_mean", "median_abs_rel_err", "max_abs_rel_err", "val_rms"};

// Every optimised cell against its paper twin (same condition, same seeds: the sweep's common
// random numbers), per method: the paired metrics and each parameter's |relative error|, with
// Holm over the compared cells per method and metric.
void compareTrajectories(const std::vector<SweepCondition>& conds, const std::map<int, Cell>& cells,
                         const std::vector<Variant>& methods, nlohmann::json& conditions) {
  std::vector<std::pair<nlohmann::json*, int>> pairs;  // (optimised cell's json, paper twin)
  for (nlohmann::json& cj : conditions) {
    const auto k = cj.at("cell").get<std::size_t>();
    if (conds[k].trajectories != "optimised") continue;
    const int twin = paperTwin(conds, k);
    if (twin >= 0 && cells.count(twin)) pairs.emplace_back(&cj, twin);
  }
  if (pairs.empty()) return;
  for (Variant v : methods) {
    const std::string name = toString(v);
    for (auto& [cj, twin] : pairs) {
      const std::map<int, const Row*>& opt = repsOf(cells.at(cj->at("cell").get<int>()), name);
      const std::map<int, const Row*>& pap = repsOf(cells.at(twin), name);
      nlohmann::json& mj = (*cj)["methods"][name];
      mj["vs_paper_trajectories"]["paper_cell"] = twin;
      const auto meanOf = [](const std::map<int, const Row*>& reps, auto get) {
        std::vector<double> x;
        for (const auto& [rep, row] : reps) {
          if (std::isfinite(get(*row))) x.push_back(get(*row));
        }
        return stats::mean(x);
      };
      for (const char* metric : kTrajectoryPaired) {
        const auto get = [&](const Row& r) { return metricOf(r, metric); };
        mj["vs_paper_trajectories"][metric] = pairedJson(pairedBy(opt, pap, get), meanOf(opt, get), meanOf(pap, get));
      }
      for (int i = 0; i < kNumParams; ++i) {
        const auto get = [i](const Row& r) { return std::abs(r.rel_best_fit[i]); };
        mj["vs_paper_trajectories"]["parameters"][std::string(ident::paramName(i))] =
            pairedJson(pairedBy(opt, pap, get), meanOf(opt, get), meanOf(pap, get));
      }
    }
    // Holm per method and metric (each parameter's error is a metric) over the compared cells, as vs_ls.
    const auto holm = [&](auto pick) {
      std::vector<nlohmann::json*> tested;
      for (auto& [cj, twin] : pairs) tested.push_back(&pick((*cj)["methods"][name]["vs_paper_trajectories"]));
      std::vector<double> ps;
      for (const nlohmann::json* j : tested) ps.push_back(j->at("p_value").is_null() ? kNaN : j->at("p_value").get<double>());
      const std::vector<double> adj = stats::holmAdjust(ps);
      for (std::size_t k = 0; k < tested.size(); ++k) (*tested[k])["p_holm"] = jnum(adj[k]);
    };
    for (const char* metric : kTrajectoryPaired) holm([&](nlohmann::json& t) -> nlohmann::json& { return t[metric]; });
    for (int i = 0; i < kNumParams; ++i) {
      const std::string pname(ident::paramName(i));
      holm([&](nlohmann::json& t) -> nlohmann::json& { return t["parameters"][pname]; });
    }
  }
}

}  // namespace

nlohmann::json sweepSummaryJson(const SweepLayout& config, const std::vector<nlohmann::json>& jobs) {
  const std::vector<Row> rows = rowsOf(config, jobs);
  const std::vector<SweepCondition> conds = config.conditions();
  std::map<int, Cell> cells;
  for (const Row& r : rows) {
    Cell& c = cells[r.cell];
    if (r.ok) {
      c.by_method[r.method][r.replicate] = &r;
    } else {
      ++c.failed[r.method];
    }
  }
  nlohmann::json out;
  out["tool"] = toolJson();
  out["config"] = config.resolved;
  out["statistics"] = {
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
      {"torque_err", "||Y (x - x_bf)|| / ||Y x_bf|| per joint on the fixed validation states (ident::validationStates)"},
      {"crb_std", "noise-limited std of each parameter for the method's own regressor, processing and structure "
                  "(experiments::noiseStd); mean over the cell's seeds"},
      {"rms_error_over_crb", "RMS over seeds of (estimate - best fit truth) / crb_std of that seed"},
      {"norm_err_*_mxt_dominated", "||x - x*|| / ||x*||: dominated by Mxt and Myt, kept for comparison only"}};
  nlohmann::json conditions = nlohmann::json::array();
  for (const auto& [cell, c] : cells) {
    nlohmann::json cj;
    cj["cell"] = cell;
    cj["condition"] = toJson(conds[static_cast<std::size_t>(cell)]);
    const std::map<int, const Row*>& ls = repsOf(c, "ls");
    for (Variant v : config.methods) {
      const std::string name = toString(v);
      const std::map<int, const Row*>& reps = repsOf(c, name);
      nlohmann::json mj;
      mj["n"] = reps.size();
      mj["n_failed"] = c.failed.count(name) ? c.failed.at(name) : 0;
      for (const Metric& m : kMetrics) {
        std::vector<double> x;
        for (const auto& [rep, row] : reps) {
          if (std::isfinite(m.get(*row))) x.push_back(m.get(*row));
        }
        const stats::ConfidenceInterval ci = stats::meanCi(x);
        mj["metrics"][m.name] = {{"mean", jnum(ci.mean)}, {"std", jnum(ci.std)}, {"ci95_low", jnum(ci.low)}, {"ci95_high", jnum(ci.high)}};
      }
      if (!ls.empty() && name != "ls") {
        for (const char* metric : kPaired) {
          const Paired p = paired(reps, ls, metric);
          mj["vs_ls"][metric] = {{"n", p.n}, {"win_rate", jnum(p.win_rate)}, {"p_value", jnum(p.p_value)}, {"mdd", jnum(p.mdd)},
                                 {"test", p.exact ? "wilcoxon exact" : "wilcoxon normal approximation"}};
        }
      }
      mj["parameters"] = parameterJson(reps);
      double ratio_max = kNaN;
      for (const auto& [pname, pj] : mj["parameters"].items()) {
        if (!pj["rms_error_over_crb"].is_null()) {
          const double r = pj["rms_error_over_crb"].get<double>();
          ratio_max = std::isfinite(ratio_max) ? std::max(ratio_max, r) : r;
        }
      }
      mj["rms_error_over_crb_max"] = jnum(ratio_max);
      cj["methods"][name] = mj;
    }
    conditions.push_back(cj);
  }
  // Holm over the cells, per method and paired metric.
  for (Variant v : config.methods) {
    for (const char* metric : kPaired) {
      std::vector<double> ps;
      for (const nlohmann::json& cj : conditions) {
        const nlohmann::json& mj = cj["methods"][toString(v)];
        ps.push_back(mj.contains("vs_ls") && !mj["vs_ls"][metric]["p_value"].is_null() ? mj["vs_ls"][metric]["p_value"].get<double>() : kNaN);
      }
      const std::vector<double> adj = stats::holmAdjust(ps);
      for (std::size_t k = 0; k < conditions.size(); ++k) {
        nlohmann::json& mj = conditions[k]["methods"][toString(v)];
        if (mj.contains("vs_ls")) mj["vs_ls"][metric]["p_holm"] = jnum(adj[k]);
      }
    }
  }
  compareTrajectories(conds, cells, config.methods, conditions);
  out["conditions"] = conditions;
  return out;
}

namespace {

double get(const nlohmann::json& j) { return j.is_null() ? kNaN : j.get<double>(); }

void writeSummaryCsv(const SweepLayout& config, const nlohmann::json& s, const std::string& path) {
  core::writeFileAtomically(path, [&](std::ostream& out) {
    out << "cell," << kConditionHeader << ",method,n,n_failed";
    for (const Metric& m : kMetrics) {
      for (const char* f : {"mean", "std", "ci95_low", "ci95_high"}) out << ',' << m.name << '_' << f;
    }
    for (const char* p : kPaired) out << ",win_rate_vs_ls_" << p << ",p_wilcoxon_vs_ls_" << p << ",p_holm_vs_ls_" << p << ",mdd_vs_ls_" << p;
    for (int i = 0; i < kNumParams; ++i) out << ",rms_error_over_crb_" << ident::paramName(i);
    out << ",rms_error_over_crb_max";
    for (const char* p : kTrajectoryPaired) out << ",win_rate_vs_paper_trajectories_" << p << ",p_holm_vs_paper_trajectories_" << p;
    out << "\n";
    const std::vector<SweepCondition> conds = config.conditions();
    for (const nlohmann::json& c : s.at("conditions")) {
      for (Variant v : config.methods) {
        const nlohmann::json& m = c.at("methods").at(toString(v));
        out << c.at("cell").get<int>() << ',' << conditionCsv(conds[c.at("cell").get<std::size_t>()]) << ',' << toString(v) << ','
            << m.at("n").get<int>() << ',' << m.at("n_failed").get<int>();
        for (const Metric& mt : kMetrics) {
          for (const char* f : {"mean", "std", "ci95_low", "ci95_high"}) out << ',' << num(get(m.at("metrics").at(mt.name).at(f)));
        }
        for (const char* p : kPaired) {
          if (m.contains("vs_ls")) {
            const nlohmann::json& q = m.at("vs_ls").at(p);
            out << ',' << num(get(q.at("win_rate"))) << ',' << num(get(q.at("p_value"))) << ',' << num(get(q.at("p_holm"))) << ','
                << num(get(q.at("mdd")));
          } else {
            out << ",,,,";
          }
        }
        for (int i = 0; i < kNumParams; ++i) out << ',' << num(get(m.at("parameters").at(std::string(ident::paramName(i))).at("rms_error_over_crb")));
        out << ',' << num(get(m.at("rms_error_over_crb_max")));
        for (const char* p : kTrajectoryPaired) {
          if (m.contains("vs_paper_trajectories")) {
            const nlohmann::json& q = m.at("vs_paper_trajectories").at(p);
            out << ',' << num(get(q.at("win_rate"))) << ',' << num(get(q.at("p_holm")));
          } else {
            out << ",,";
          }
        }
        out << '\n';
      }
    }
  });
}

std::string ciText(const nlohmann::json& m, double scale, int decimals) {
  const double mean = get(m.at("mean")), lo = get(m.at("ci95_low")), hi = get(m.at("ci95_high"));
  if (!std::isfinite(mean)) return "-";
  std::string s = fixed(scale * mean, decimals);
  if (std::isfinite(lo)) s += " [" + fixed(scale * lo, decimals) + ", " + fixed(scale * hi, decimals) + "]";
  return s;
}

// "P -> O (win rate, Holm p)" of one paired trajectory comparison, in % when scale is 100.
std::string trajectoryPairText(const nlohmann::json& p, double scale, int decimals) {
  const double o = get(p.at("optimised_mean")), q = get(p.at("paper_mean"));
  if (!std::isfinite(o) || !std::isfinite(q)) return "-";
  return fixed(scale * q, decimals) + " -> " + fixed(scale * o, decimals) + " (" + fixed(get(p.at("win_rate")), 2) +
         ", p = " + fmt(get(p.at("p_holm")), 2) + ")";
}

// The trajectory axis: each optimised cell against its paper twin, grouped like the sections.
void writeTrajectoryComparisonMd(const SweepLayout& config, const nlohmann::json& s, std::ostream& md) {
  std::map<std::string, std::vector<const nlohmann::json*>> groups;
  std::vector<std::string> order;
  for (const nlohmann::json& c : s.at("conditions")) {
    if (c.at("methods").empty() || !c.at("methods").begin()->contains("vs_paper_trajectories")) continue;
    const nlohmann::json& k = c.at("condition");
    const std::string key = "cylinder mass scale " + fmt(k.at("cylinder_mass_scale").get<double>()) + ", vibration level " +
                            fmt(k.at("vibration_level").get<double>()) + ", angle noise " + fmt(k.at("angle_noise_deg").get<double>()) +
                            " deg, quantisation " + fmt(k.at("quantisation_deg").get<double>()) + " deg";
    if (!groups.count(key)) order.push_back(key);
    groups[key].push_back(&c);
  }
  if (order.empty()) return;
  md << "\n# Optimised vs the paper's identification trajectories\n\nEach optimised cell against the paper cell with the "
        "same condition and the same seeds (validation on trajectories 2 and 4 in both): paper -> optimised mean over seeds "
        "(share of seeds where optimised is better, Wilcoxon signed-rank p, Holm-adjusted over the compared cells per method "
        "and metric).\n";
  for (const std::string& key : order) {
    const auto& cs = groups[key];
    std::vector<std::string> header{"method"};
    for (const nlohmann::json* c : cs) header.push_back("tau noise " + fmt(c->at("condition").at("torque_noise_Nm").get<double>()) + " N m");
    md << "\n## " << key << "\n";
    for (const char* metric : {"torque_err_mean", "median_abs_rel_err", "max_abs_rel_err"}) {
      md << "\n" << (std::string(metric) == "torque_err_mean" ? "Torque-space error (%)"
                     : std::string(metric) == "median_abs_rel_err" ? "Median per-parameter |error| (%)"
                                                                    : "Worst per-parameter |error| (%)")
         << "\n\n";
      TextTable t(header);
      for (Variant v : config.methods) {
        std::vector<std::string> row{toString(v)};
        for (const nlohmann::json* c : cs) row.push_back(trajectoryPairText(c->at("methods").at(toString(v)).at("vs_paper_trajectories").at(metric), 100.0, 2));
        t.addRow(row);
      }
      t.printMarkdown(md);
    }
    for (const char* method : {"ls", "rls-pso"}) {
      if (!cs.front()->at("methods").contains(method)) continue;
      md << "\n" << method << ": per-parameter |error| (%)\n\n";
      std::vector<std::string> ph{"param"};
      for (std::size_t k = 1; k < header.size(); ++k) ph.push_back(header[k]);
      TextTable t(ph);
      for (int i = 0; i < kNumParams; ++i) {
        const std::string pname(ident::paramName(i));
        std::vector<std::string> row{pname};
        for (const nlohmann::json* c : cs) {
          row.push_back(trajectoryPairText(c->at("methods").at(method).at("vs_paper_trajectories").at("parameters").at(pname), 100.0, 2));
        }
        t.addRow(row);
      }
      t.printMarkdown(md);
    }
  }
}

// One section per (cylinder, vibration, angle noise, quantisation): methods (rows) x torque noise
// (columns) for the torque-space error, the median and worst per-parameter error, the worst
// error in units of the method's CRB, and RLS-PSO vs LS.
void writeSummaryMd(const SweepLayout& config, const nlohmann::json& s, const std::string& path) {
  core::writeFileAtomically(path, [&](std::ostream& md) {
    md << "# Sweep summary\n\nMean over seeds [95 % Student-t CI]. Torque-space error: ||Y (x - x_bf)|| / ||Y x_bf|| on the "
          "fixed validation states, mean of hip and knee, in %. Per-parameter error: median (worst) over the 10 parameters "
          "of |x_i - x_bf,i| / |x_bf,i|, in %. Error/CRB: the largest over parameters of RMS(error) / (the method's "
          "noise-limited std). Paired comparison: Wilcoxon signed-rank vs LS over the same seeds, Holm-adjusted over the "
          "sweep's cells; MDD = minimal detectable difference at 80 % power.\n";
    std::map<std::string, std::vector<const nlohmann::json*>> groups;
    std::vector<std::string> order;
    for (const nlohmann::json& c : s.at("conditions")) {
      const nlohmann::json& k = c.at("condition");
      const std::string key = (k.value("trajectories", std::string("paper")) == "optimised" ? std::string("optimised trajectories, ")
                                                                                             : std::string("paper's trajectories, ")) +
                              "cylinder mass scale " + fmt(k.at("cylinder_mass_scale").get<double>()) + ", vibration level " +
                              fmt(k.at("vibration_level").get<double>()) + ", angle noise " +
                              fmt(k.at("angle_noise_deg").get<double>()) + " deg, quantisation " +
                              fmt(k.at("quantisation_deg").get<double>()) + " deg";
      if (!groups.count(key)) order.push_back(key);
      groups[key].push_back(&c);
    }
    const auto cellText = [](const nlohmann::json& m, const char* what) -> std::string {
      const nlohmann::json& mt = m.at("metrics");
      if (std::string(what) == "torque") return ciText(mt.at("torque_err_mean"), 100.0, 2);
      if (std::string(what) == "params") {
        const double med = get(mt.at("median_abs_rel_err").at("mean")), worst = get(mt.at("max_abs_rel_err").at("mean"));
        return std::isfinite(med) ? fixed(100.0 * med, 1) + " (" + fixed(100.0 * worst, 1) + ")" : "-";
      }
      const double r = get(m.at("rms_error_over_crb_max"));
      return std::isfinite(r) ? fmt(r, 3) : "-";
    };
    for (const std::string& key : order) {
      const auto& cs = groups[key];
      md << "\n## " << key << "\n";
      for (const char* what : {"torque", "params", "crb"}) {
        md << "\n" << (std::string(what) == "torque" ? "Torque-space error (%)" : std::string(what) == "params" ? "Per-parameter |error| (%): median (worst)" : "Worst RMS error / CRB") << "\n\n";
        std::vector<std::string> header{"method"};
        for (const nlohmann::json* c : cs) header.push_back("tau noise " + fmt(c->at("condition").at("torque_noise_Nm").get<double>()) + " N m");
        TextTable t(header);
        for (Variant v : config.methods) {
          std::vector<std::string> row{toString(v)};
          for (const nlohmann::json* c : cs) row.push_back(cellText(c->at("methods").at(toString(v)), what));
          t.addRow(row);
        }
        t.printMarkdown(md);
      }
      // Every method against LS on the torque-space error: is it closer to the truth, significantly?
      {
        std::vector<std::string> header{"method"};
        for (const nlohmann::json* c : cs) header.push_back("tau noise " + fmt(c->at("condition").at("torque_noise_Nm").get<double>()) + " N m");
        TextTable t(header);
        bool any = false;
        for (Variant v : config.methods) {
          std::vector<std::string> row{toString(v)};
          bool have = false;
          for (const nlohmann::json* c : cs) {
            const nlohmann::json& m = c->at("methods").at(toString(v));
            if (!m.contains("vs_ls")) {
              row.push_back("-");
              continue;
            }
            have = true;
            const nlohmann::json& p = m.at("vs_ls").at("torque_err_mean");
            row.push_back(fixed(get(p.at("win_rate")), 2) + ", p = " + fmt(get(p.at("p_holm")), 3) + ", n = " +
                          core::toText(p.at("n").get<long>()));
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
      bool have_pair = false;
      for (const nlohmann::json* c : cs) have_pair = have_pair || (c->at("methods").contains("rls-pso") && c->at("methods").at("rls-pso").contains("vs_ls"));
      if (!have_pair) continue;
      md << "\nRLS-PSO vs LS (win rate, Holm-adjusted p, MDD)\n\n";
      std::vector<std::string> header{"metric"};
      for (const nlohmann::json* c : cs) header.push_back("tau noise " + fmt(c->at("condition").at("torque_noise_Nm").get<double>()) + " N m");
      TextTable t(header);
      for (const char* metric : kPaired) {
        std::vector<std::string> row{metric};
        for (const nlohmann::json* c : cs) {
          const nlohmann::json& p = c->at("methods").at("rls-pso").at("vs_ls").at(metric);
          const double scale = std::string(metric) == "torque_err_mean" ? 100.0 : 1.0;
          row.push_back(fixed(get(p.at("win_rate")), 2) + ", p = " + fmt(get(p.at("p_holm")), 3) + ", MDD " +
                        fmt(scale * get(p.at("mdd")), 3) + (scale == 100.0 ? " %" : " N m"));
        }
        t.addRow(row);
      }
      t.printMarkdown(md);
    }
    writeTrajectoryComparisonMd(config, s, md);
  });
}

}  // namespace

void writeSweepTables(const SweepLayout& config, const std::vector<nlohmann::json>& jobs, const std::string& dir) {
  writeRunsCsv(config, rowsOf(config, jobs), dir + "/runs.csv");
  const nlohmann::json s = sweepSummaryJson(config, jobs);
  writeJsonFile(dir + "/summary.json", s);
  testKillPoint("sweep-tables");
  writeSummaryCsv(config, s, dir + "/summary.csv");
  writeSummaryMd(config, s, dir + "/summary.md");
}

}  // namespace exoid::experiments
