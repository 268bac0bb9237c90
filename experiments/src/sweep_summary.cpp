#include "exoid/experiments/sweep_summary.hpp"

#include "exoid/experiments/identification.hpp"
#include "exoid/experiments/stats.hpp"
#include "exoid/experiments/table.hpp"
#include "exoid/ident/atomic_file.hpp"
#include "exoid/ident/metrics.hpp"
#include "exoid/ident/params.hpp"

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
  double err_rigid = kNaN, err_best_fit = kNaN;
  Eigen::VectorXd rel_best_fit = Eigen::VectorXd::Constant(kNumParams, kNaN);
  Eigen::VectorXd abs_best_fit = Eigen::VectorXd::Constant(kNumParams, kNaN);
  double val[6] = {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};  // knee mean/std/rms, hip mean/std/rms
  double wall_time_s = kNaN;
};

Eigen::VectorXd vec(const nlohmann::json& j) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(j.size()));
  for (std::size_t i = 0; i < j.size(); ++i) v[static_cast<Eigen::Index>(i)] = j[i].get<double>();
  return v;
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
      r.abs_best_fit = eb.abs;
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
         num(c.vibration_level) + "," + num(c.cylinder_mass_scale);
}
const char* kConditionHeader = "torque_noise_Nm,angle_noise_deg,quantisation_deg,vibration_level,cylinder_mass_scale";

// The summary metrics: name and how to read it from a row.
struct Metric {
  const char* name;
  double (*get)(const Row&);
};
const Metric kMetrics[] = {
    {"err_best_fit", [](const Row& r) { return r.err_best_fit; }},
    {"err_rigid", [](const Row& r) { return r.err_rigid; }},
    {"knee_val_mean_abs", [](const Row& r) { return r.val[0]; }},
    {"knee_val_rms", [](const Row& r) { return r.val[2]; }},
    {"hip_val_mean_abs", [](const Row& r) { return r.val[3]; }},
    {"hip_val_rms", [](const Row& r) { return r.val[5]; }},
    {"val_rms", [](const Row& r) { return 0.5 * (r.val[2] + r.val[5]); }},
};
// Paired comparisons against LS run on these.
const char* kPaired[] = {"err_best_fit", "val_rms"};

double metricOf(const Row& r, const std::string& name) {
  for (const Metric& m : kMetrics) {
    if (name == m.name) return m.get(r);
  }
  return kNaN;
}

struct Cell {
  std::map<std::string, std::map<int, const Row*>> by_method;  // method -> replicate -> row (ok only)
  std::map<std::string, int> failed;
  Eigen::VectorXd crb_sum = Eigen::VectorXd::Zero(kNumParams);
  int crb_n = 0;
};

void writeRunsCsv(const SweepLayout& config, const std::vector<Row>& rows, const std::string& path) {
  const std::vector<SweepCondition> conds = config.conditions();
  ident::writeFileAtomically(path, [&](std::ostream& out) {
    out << "cell,replicate," << kConditionHeader << ",seed,method,status,err_rigid,err_best_fit";
    for (int i = 0; i < kNumParams; ++i) out << ",rel_err_" << ident::paramName(i);
    out << ",knee_val_mean_abs,knee_val_std_abs,knee_val_rms,hip_val_mean_abs,hip_val_std_abs,hip_val_rms,message,wall_time_s\n";
    for (const Row& r : rows) {
      out << r.cell << ',' << r.replicate << ',' << conditionCsv(conds[static_cast<std::size_t>(r.cell)]) << ',' << r.seed << ','
          << r.method << ',' << r.status << ',' << num(r.err_rigid) << ',' << num(r.err_best_fit);
      for (int i = 0; i < kNumParams; ++i) out << ',' << num(r.rel_best_fit[i]);
      for (double v : r.val) out << ',' << num(v);
      out << ',' << csvQuote(r.message) << ',' << num(r.wall_time_s) << '\n';
    }
  });
}

struct Paired {
  int n = 0;
  double win_rate = kNaN, p_value = kNaN, median_diff = kNaN;
  bool exact = false;
};
Paired paired(const std::map<int, const Row*>& m, const std::map<int, const Row*>& ls, const std::string& metric) {
  std::vector<double> a, b;
  for (const auto& [rep, row] : m) {
    const auto it = ls.find(rep);
    if (it == ls.end()) continue;
    a.push_back(metricOf(*row, metric));
    b.push_back(metricOf(*it->second, metric));
  }
  Paired p;
  p.n = static_cast<int>(a.size());
  if (a.empty()) return p;
  double wins = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) wins += a[i] < b[i] ? 1.0 : (a[i] == b[i] ? 0.5 : 0.0);
  p.win_rate = wins / static_cast<double>(a.size());
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
    c.methods.clear();
    for (const auto& m : resolved.at("sweep").at("methods")) c.methods.push_back(parseVariant(m.get<std::string>()));
    return {c.conditions(), c.methods, resolved.at("sweep").at("seeds").get<int>(), resolved};
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("malformed sweep configuration (config.json): ") + e.what());
  }
}

nlohmann::json sweepSummaryJson(const SweepLayout& config, const std::vector<nlohmann::json>& jobs) {
  const std::vector<Row> rows = rowsOf(config, jobs);
  const std::vector<SweepCondition> conds = config.conditions();
  std::map<int, Cell> cells;
  for (const nlohmann::json& job : jobs) {
    if (job.at("status") != "ok") continue;
    Cell& c = cells[job.at("cell").get<int>()];
    c.crb_sum += vec(job.at("crb_std"));
    ++c.crb_n;
  }
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
      {"win_rate", "fraction of seeds where the method's value < ls's (ties count 1/2)"},
      {"crb_std", "Cramer-Rao lower bound of each parameter's std: exact-state regressors of the knee stage "
                  "(record 1) and hip stage (record 3), sigma = torque noise; mean over the cell's seeds"},
      {"rms_error_over_crb", "RMS over seeds of (estimate - best fit truth) / crb_std, per parameter"}};
  nlohmann::json conditions = nlohmann::json::array();
  for (const auto& [cell, c] : cells) {
    nlohmann::json cj;
    cj["cell"] = cell;
    cj["condition"] = toJson(conds[static_cast<std::size_t>(cell)]);
    Eigen::VectorXd crb = Eigen::VectorXd::Constant(kNumParams, kNaN);
    if (c.crb_n > 0) crb = c.crb_sum / c.crb_n;
    for (int i = 0; i < kNumParams; ++i) cj["crb_std"][std::string(ident::paramName(i))] = jnum(crb[i]);
    const auto ls = c.by_method.find("ls");
    for (Variant v : config.methods) {
      const std::string name = toString(v);
      nlohmann::json mj;
      const auto it = c.by_method.find(name);
      const std::map<int, const Row*> empty;
      const std::map<int, const Row*>& reps = it == c.by_method.end() ? empty : it->second;
      mj["n"] = reps.size();
      mj["n_failed"] = c.failed.count(name) ? c.failed.at(name) : 0;
      for (const Metric& m : kMetrics) {
        std::vector<double> x;
        for (const auto& [rep, row] : reps) x.push_back(m.get(*row));
        const stats::ConfidenceInterval ci = stats::meanCi(x);
        mj["metrics"][m.name] = {{"mean", jnum(ci.mean)}, {"std", jnum(ci.std)}, {"ci95_low", jnum(ci.low)}, {"ci95_high", jnum(ci.high)}};
      }
      if (ls != c.by_method.end() && name != "ls") {
        for (const char* metric : kPaired) {
          const Paired p = paired(reps, ls->second, metric);
          mj["vs_ls"][metric] = {{"n", p.n}, {"win_rate", jnum(p.win_rate)}, {"p_value", jnum(p.p_value)},
                                 {"test", p.exact ? "wilcoxon exact" : "wilcoxon normal approximation"}};
        }
      }
      double ratio_sum = 0.0, ratio_max = kNaN;
      int ratio_n = 0;
      for (int i = 0; i < kNumParams; ++i) {
        double ss = 0.0;
        for (const auto& [rep, row] : reps) ss += row->abs_best_fit[i] * row->abs_best_fit[i];
        const double rms = reps.empty() ? kNaN : std::sqrt(ss / static_cast<double>(reps.size()));
        const double ratio = crb[i] > 0.0 ? rms / crb[i] : kNaN;
        mj["rms_error"][std::string(ident::paramName(i))] = jnum(rms);
        mj["rms_error_over_crb"][std::string(ident::paramName(i))] = jnum(ratio);
        if (std::isfinite(ratio)) {
          ratio_sum += ratio;
          ++ratio_n;
          ratio_max = std::isfinite(ratio_max) ? std::max(ratio_max, ratio) : ratio;
        }
      }
      mj["rms_error_over_crb_mean"] = jnum(ratio_n ? ratio_sum / ratio_n : kNaN);
      mj["rms_error_over_crb_max"] = jnum(ratio_max);
      cj["methods"][name] = mj;
    }
    conditions.push_back(cj);
  }
  out["conditions"] = conditions;
  return out;
}

namespace {

double get(const nlohmann::json& j) { return j.is_null() ? kNaN : j.get<double>(); }

void writeSummaryCsv(const SweepLayout& config, const nlohmann::json& s, const std::string& path) {
  ident::writeFileAtomically(path, [&](std::ostream& out) {
    out << "cell," << kConditionHeader << ",method,n,n_failed";
    for (const Metric& m : kMetrics) {
      for (const char* f : {"mean", "std", "ci95_low", "ci95_high"}) out << ',' << m.name << '_' << f;
    }
    for (const char* p : kPaired) out << ",win_rate_vs_ls_" << p << ",p_wilcoxon_vs_ls_" << p;
    out << ",rms_error_over_crb_mean,rms_error_over_crb_max\n";
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
            out << ',' << num(get(m["vs_ls"][p]["win_rate"])) << ',' << num(get(m["vs_ls"][p]["p_value"]));
          } else {
            out << ",,";
          }
        }
        out << ',' << num(get(m.at("rms_error_over_crb_mean"))) << ',' << num(get(m.at("rms_error_over_crb_max"))) << '\n';
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

// One markdown table per (cylinder, vibration, angle noise, quantisation): parameter error norm
// vs best fit (%) per method (rows) and torque noise (columns), then RLS-PSO vs LS.
void writeSummaryMd(const SweepLayout& config, const nlohmann::json& s, const std::string& path) {
  ident::writeFileAtomically(path, [&](std::ostream& md) {
    md << "# Sweep summary\n\nParameter error norm vs the best-fit truth, ||x - x_bf|| / ||x_bf||, in %: mean over seeds "
          "[95 % Student-t CI]. Paired comparison: Wilcoxon signed-rank vs LS over the same seeds.\n";
    std::map<std::string, std::vector<const nlohmann::json*>> groups;
    std::vector<std::string> order;
    for (const nlohmann::json& c : s.at("conditions")) {
      const nlohmann::json& k = c.at("condition");
      const std::string key = "cylinder mass scale " + fmt(k.at("cylinder_mass_scale").get<double>()) + ", vibration level " +
                              fmt(k.at("vibration_level").get<double>()) + ", angle noise " +
                              fmt(k.at("angle_noise_deg").get<double>()) + " deg, quantisation " +
                              fmt(k.at("quantisation_deg").get<double>()) + " deg";
      if (!groups.count(key)) order.push_back(key);
      groups[key].push_back(&c);
    }
    for (const std::string& key : order) {
      const auto& cs = groups[key];
      md << "\n## " << key << "\n\n";
      std::vector<std::string> header{"method"};
      for (const nlohmann::json* c : cs) header.push_back("tau noise " + fmt(c->at("condition").at("torque_noise_Nm").get<double>()) + " N m");
      TextTable t(header);
      for (Variant v : config.methods) {
        std::vector<std::string> row{toString(v)};
        for (const nlohmann::json* c : cs) row.push_back(ciText(c->at("methods").at(toString(v)).at("metrics").at("err_best_fit"), 100.0, 2));
        t.addRow(row);
      }
      bool have_pair = false;
      for (const nlohmann::json* c : cs) have_pair = have_pair || (c->at("methods").contains("rls-pso") && c->at("methods").at("rls-pso").contains("vs_ls"));
      if (have_pair) {
        for (const char* metric : kPaired) {
          std::vector<std::string> row{std::string("rls-pso vs ls (") + metric + "): win rate, p"};
          for (const nlohmann::json* c : cs) {
            const nlohmann::json& p = c->at("methods").at("rls-pso").at("vs_ls").at(metric);
            row.push_back(fixed(get(p.at("win_rate")), 2) + ", p = " + fmt(get(p.at("p_value")), 3));
          }
          t.addRow(row);
        }
      }
      std::vector<std::string> row{"CRB-relative RMS error of rls-pso (mean over params)"};
      for (const nlohmann::json* c : cs) {
        const auto& m = c->at("methods");
        row.push_back(m.contains("rls-pso") ? (m.at("rls-pso").at("rms_error_over_crb_mean").is_null() ? "-" : fmt(get(m.at("rls-pso").at("rms_error_over_crb_mean")), 3)) : "-");
      }
      t.addRow(row);
      t.printMarkdown(md);
    }
  });
}

}  // namespace

void writeSweepTables(const SweepLayout& config, const std::vector<nlohmann::json>& jobs, const std::string& dir) {
  writeRunsCsv(config, rowsOf(config, jobs), dir + "/runs.csv");
  const nlohmann::json s = sweepSummaryJson(config, jobs);
  writeJsonFile(dir + "/summary.json", s);
  writeSummaryCsv(config, s, dir + "/summary.csv");
  writeSummaryMd(config, s, dir + "/summary.md");
}

}  // namespace exoid::experiments
