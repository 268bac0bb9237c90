// A chain sweep's tables: runs.csv (a row per run and method), and per cell and method over the
// seeds: each score's mean and 95 % CI, a paired Wilcoxon test against LS (Holm over the cells),
// each base parameter's error, and how LS's standard errors compare with its actual errors.
#include "exoid/experiments/sweep/robot_sweep.hpp"

#include "exoid/core/atomic_file.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/report/cells.hpp"
#include "exoid/experiments/report/stats.hpp"
#include "exoid/experiments/report/table.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

namespace exoid::experiments {

// Named, not anonymous: the unity build puts this file beside the APAL sweep's own helpers.
namespace chain_sweep_tables {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A base parameter's error is relative (to |truth|) unless its truth is zero (up to rounding of
// the combination): then only its absolute error and z are reported.
bool hasRelativeError(const std::vector<double>& truth, std::size_t i) {
  double scale = 0.0;
  for (double t : truth) scale = std::max(scale, std::abs(t));
  return std::abs(truth[i]) > 1e-12 * scale;
}

// One run's one method.
struct Row {
  int cell = 0, replicate = 0;
  std::uint64_t seed = 0;
  std::string method, status, message;
  bool ok = false;
  std::vector<double> error;      ///< x - truth, per base parameter
  std::vector<double> rel_error;  ///< (x - truth) / |truth|, NaN where the truth is zero
  std::vector<double> z;          ///< LS: error / its standard error; else empty
  std::vector<double> se;         ///< LS: its standard errors; else empty
  double median_abs_rel = kNaN, max_abs_rel = kNaN, torque_err = kNaN, val_rms = kNaN;
};

struct Metric {
  const char* name;
  const char* meaning;
  double Row::*value;
};
const Metric kMetrics[] = {
    {"median_abs_rel_err", "median over the base parameters with a non-zero truth of |x - truth| / |truth|", &Row::median_abs_rel},
    {"max_abs_rel_err", "the largest of them", &Row::max_abs_rel},
    {"torque_err_mean", "mean over the joints of ||Wv (x - truth)|| / ||Wv truth|| on the validation record", &Row::torque_err},
    {"val_rms_mean_Nm", "mean over the joints of the validation record's RMS torque error (measured - predicted), N m", &Row::val_rms},
};

// A cell's base parameters and their truth (a vibrating cell's include its base-motion ones).
struct ParameterSet {
  std::vector<std::string> names;
  std::vector<double> truth;
};
using ParameterSets = std::map<int, ParameterSet>;  // by cell

std::vector<Row> rowsOf(const std::vector<nlohmann::json>& jobs, ParameterSets& sets) {
  std::vector<Row> rows;
  for (const nlohmann::json& j : jobs) {
    Row base;
    base.cell = j.at("cell").get<int>();
    base.replicate = j.at("replicate").get<int>();
    base.seed = j.at("seed").get<std::uint64_t>();
    if (j.at("status") != "ok") {
      base.method = "*";
      base.status = "error";
      base.message = j.at("message").get<std::string>();
      rows.push_back(base);
      continue;
    }
    const std::vector<double> t = j.at("truth").get<std::vector<double>>();
    if (!sets.count(base.cell)) sets[base.cell] = {j.at("base_parameters").get<std::vector<std::string>>(), t};
    for (const nlohmann::json& m : j.at("methods")) {
      Row r = base;
      r.method = m.at("method").get<std::string>();
      r.status = m.at("status").get<std::string>();
      r.message = m.at("message").get<std::string>();
      r.ok = r.status == "ok";
      const std::vector<double> x = m.at("x").get<std::vector<double>>();
      std::vector<double> abs_rel;
      for (std::size_t i = 0; i < x.size() && i < t.size(); ++i) {
        r.error.push_back(x[i] - t[i]);
        r.rel_error.push_back(hasRelativeError(t, i) ? (x[i] - t[i]) / std::abs(t[i]) : kNaN);
        if (hasRelativeError(t, i)) abs_rel.push_back(std::abs(r.rel_error.back()));
      }
      if (m.contains("std_error")) {
        const std::vector<double> se = m.at("std_error").get<std::vector<double>>();
        for (std::size_t i = 0; i < se.size() && i < r.error.size(); ++i) r.z.push_back(se[i] > 0.0 ? r.error[i] / se[i] : kNaN);
        r.se = se;
      }
      if (!abs_rel.empty()) {
        r.median_abs_rel = stats::median(abs_rel);
        r.max_abs_rel = *std::max_element(abs_rel.begin(), abs_rel.end());
      }
      r.torque_err = stats::mean(m.at("torque_err_rel").get<std::vector<double>>());
      r.val_rms = stats::mean(m.at("val_rms_Nm").get<std::vector<double>>());
      rows.push_back(r);
    }
  }
  return rows;
}

std::string pct(double v, int digits = 3) { return std::isfinite(v) ? fmt(100.0 * v, digits) : "-"; }

// Every cell's base parameters, in the order they first appear.
std::vector<std::string> allNames(const ParameterSets& sets) {
  std::vector<std::string> names;
  for (const auto& [cell, set] : sets) {
    for (const std::string& n : set.names) {
      if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
    }
  }
  return names;
}

void writeRunsCsv(const SweepLayout& layout, const std::vector<Row>& rows, const ParameterSets& sets, const std::vector<nlohmann::json>& jobs,
                  const std::string& path) {
  std::map<std::pair<int, int>, double> wall;
  for (const nlohmann::json& j : jobs) wall[{j.at("cell").get<int>(), j.at("replicate").get<int>()}] = j.at("wall_time_s").get<double>();
  const std::vector<std::string> names = allNames(sets);
  core::writeFileAtomically(path, [&](std::ostream& out) {
    out << "cell,replicate,seed," << kConditionCsvHeader << ",method,status";
    for (const Metric& m : kMetrics) out << "," << m.name;
    for (const std::string& n : names) out << "," << csvField("error " + n);
    out << ",message,wall_time_s\n";
    for (const Row& r : rows) {
      out << r.cell << "," << r.replicate << "," << r.seed << "," << conditionCsv(layout.cells.at(static_cast<std::size_t>(r.cell))) << ","
          << r.method << "," << r.status;
      for (const Metric& m : kMetrics) out << "," << csvNumber(r.*m.value);
      const auto set = sets.find(r.cell);
      for (const std::string& n : names) {
        std::size_t i = 0;
        if (set != sets.end()) i = static_cast<std::size_t>(std::find(set->second.names.begin(), set->second.names.end(), n) - set->second.names.begin());
        out << "," << (set != sets.end() && i < r.error.size() ? csvNumber(r.error[i]) : std::string());
      }
      out << "," << csvField(r.message) << "," << csvNumber(wall[{r.cell, r.replicate}]) << "\n";
    }
  });
}

// A method in a cell: its ok rows by replicate.
using Replicates = std::map<int, const Row*>;

struct MethodCell {
  std::string method;
  int n = 0, n_failed = 0;
  std::vector<stats::ConfidenceInterval> metrics;  // kMetrics' order
  // Against LS on the seeds both have: median |rel err| and torque error.
  PairedComparison rel, torque;
  std::vector<stats::ConfidenceInterval> rel_error;  // per base parameter (NaN-free values only)
  std::vector<double> abs_rel_median, abs_error_rms, z_rms;
  std::vector<stats::Coverage> coverage;  ///< of estimate -+ 1.96 standard errors (LS; n = 0 for others)
};

struct CellTables {
  int cell = 0;
  std::vector<MethodCell> methods;
};

MethodCell summarizeMethod(const std::string& method, const Replicates& reps, int failed, const Replicates* ls, std::size_t n_params) {
  MethodCell m;
  m.method = method;
  m.n = static_cast<int>(reps.size());
  m.n_failed = failed;
  for (const Metric& metric : kMetrics) {
    std::vector<double> x;
    for (const auto& [rep, row] : reps) {
      if (std::isfinite(row->*metric.value)) x.push_back(row->*metric.value);
    }
    m.metrics.push_back(stats::meanCi(x));
  }
  for (std::size_t i = 0; i < n_params; ++i) {
    std::vector<double> rel, abs_rel, errors, ses;
    double e2 = 0.0, z2 = 0.0;
    int zn = 0;
    for (const auto& [rep, row] : reps) {
      if (i < row->se.size()) {
        errors.push_back(row->error[i]);
        ses.push_back(row->se[i]);
      }
      if (std::isfinite(row->rel_error[i])) {
        rel.push_back(row->rel_error[i]);
        abs_rel.push_back(std::abs(row->rel_error[i]));
      }
      e2 += row->error[i] * row->error[i];
      if (i < row->z.size() && std::isfinite(row->z[i])) {
        z2 += row->z[i] * row->z[i];
        ++zn;
      }
    }
    m.rel_error.push_back(stats::meanCi(rel));
    m.abs_rel_median.push_back(stats::median(abs_rel));
    m.abs_error_rms.push_back(reps.empty() ? kNaN : std::sqrt(e2 / static_cast<double>(reps.size())));
    m.z_rms.push_back(zn ? std::sqrt(z2 / zn) : kNaN);
    m.coverage.push_back(stats::coverageOf(errors, ses));
  }
  if (ls && method != "ls") {
    std::vector<double> a_rel, b_rel, a_t, b_t;
    for (const auto& [rep, row] : reps) {
      const auto it = ls->find(rep);
      if (it == ls->end()) continue;
      a_rel.push_back(row->median_abs_rel);
      b_rel.push_back(it->second->median_abs_rel);
      a_t.push_back(row->torque_err);
      b_t.push_back(it->second->torque_err);
    }
    m.rel = pairedValues(a_rel, b_rel);
    m.torque = pairedValues(a_t, b_t);
  }
  return m;
}

std::vector<CellTables> summarize(const SweepLayout& layout, const std::vector<Row>& rows, const ParameterSets& sets) {
  std::map<int, std::map<std::string, Replicates>> ok;
  std::map<int, std::map<std::string, int>> failed;
  std::map<int, bool> seen;
  for (const Row& r : rows) {
    seen[r.cell] = true;
    if (r.method == "*") {
      for (const std::string& m : layout.method_names) ++failed[r.cell][m];
    } else if (r.ok) {
      ok[r.cell][r.method][r.replicate] = &r;
    } else {
      ++failed[r.cell][r.method];
    }
  }
  std::vector<CellTables> cells;
  for (const auto& [cell, _] : seen) {
    CellTables c;
    c.cell = cell;
    const auto ls_it = ok[cell].find("ls");
    const Replicates* ls = ls_it == ok[cell].end() ? nullptr : &ls_it->second;
    const auto set = sets.find(cell);
    const std::size_t n_params = set == sets.end() ? 0 : set->second.names.size();
    for (const std::string& m : layout.method_names) c.methods.push_back(summarizeMethod(m, ok[cell][m], failed[cell][m], ls, n_params));
    cells.push_back(std::move(c));
  }
  // Holm over the cells, per method and score.
  for (const std::string& method : layout.method_names) {
    std::vector<PairedComparison*> rel, torque;
    for (CellTables& c : cells) {
      for (MethodCell& m : c.methods) {
        if (m.method != method) continue;
        rel.push_back(&m.rel);
        torque.push_back(&m.torque);
      }
    }
    holmAdjustFamily(rel);
    holmAdjustFamily(torque);
  }
  return cells;
}

nlohmann::json ciJson(const stats::ConfidenceInterval& c) {
  return {{"n", c.n}, {"mean", jsonNumber(c.n ? c.mean : kNaN)}, {"std", jsonNumber(c.std)}, {"ci95_low", jsonNumber(c.low)}, {"ci95_high", jsonNumber(c.high)}};
}

nlohmann::json summaryJson(const SweepLayout& layout, const std::vector<CellTables>& cells, const ParameterSets& sets) {
  nlohmann::json j;
  j["tool"] = toolJson();
  j["config"] = layout.resolved;
  nlohmann::json meanings = nlohmann::json::object();
  for (const Metric& m : kMetrics) meanings[m.name] = m.meaning;
  j["statistics"] = {{"metrics", meanings},
                     {"ci", "mean over the seeds with an estimate, 95 % Student-t interval"},
                     {"vs_ls", "paired Wilcoxon signed-rank test on the seeds both have (two-sided); win rate = share of seeds with the "
                               "lower value, ties 1/2; Holm over the cells, per method and score"},
                     {"parameters", "rel_err: signed (x - truth) / |truth| (null where the truth is zero); abs_err_rms: RMS of x - truth; z_rms: LS only, RMS over the "
                                    "seeds of (x - truth) / its own standard error (1 when the standard errors are honest); coverage95: LS only, the "
                                    "share of seeds whose x -+ 1.96 standard errors held the truth, its Wilson 95 % interval, the mean error and the "
                                    "scatter in standard errors"}};
  // As the APAL sweep's summary.json: conditions, each with its methods and parameters by name.
  j["conditions"] = nlohmann::json::array();
  for (const CellTables& c : cells) {
    const ParameterSet set = sets.count(c.cell) ? sets.at(c.cell) : ParameterSet{};
    const std::vector<std::string>& names = set.names;
    nlohmann::json cj = {{"cell", c.cell},
                         {"condition", toJson(layout.cells.at(static_cast<std::size_t>(c.cell)))},
                         {"base_parameters", {{"names", names}, {"truth", set.truth}}},
                         {"methods", nlohmann::json::object()}};
    for (const MethodCell& m : c.methods) {
      nlohmann::json mj = {{"n", m.n}, {"n_failed", m.n_failed}};
      for (std::size_t k = 0; k < std::size(kMetrics); ++k) mj["metrics"][kMetrics[k].name] = ciJson(m.metrics[k]);
      if (m.method != "ls") {
        const auto paired = [](const PairedComparison& p) {
          return nlohmann::json{{"win_rate", jsonNumber(p.win_rate)}, {"p_value", jsonNumber(p.p_value)}, {"p_holm", jsonNumber(p.p_holm)}};
        };
        mj["vs_ls"] = {{"n", m.rel.n}, {"median_abs_rel_err", paired(m.rel)}, {"torque_err_mean", paired(m.torque)}};
      }
      mj["parameters"] = nlohmann::json::object();
      for (std::size_t i = 0; i < names.size(); ++i) {
        mj["parameters"][names[i]] = {{"rel_err", ciJson(m.rel_error[i])}, {"abs_rel_err_median", jsonNumber(m.abs_rel_median[i])},
                                      {"abs_err_rms", jsonNumber(m.abs_error_rms[i])}, {"z_rms", jsonNumber(m.z_rms[i])}};
        if (m.coverage[i].n > 0) mj["parameters"][names[i]]["coverage95"] = coverageJson(m.coverage[i]);
      }
      cj["methods"][m.method] = mj;
    }
    j["conditions"].push_back(cj);
  }
  return j;
}

void writeSummaryCsv(const SweepLayout& layout, const std::vector<CellTables>& cells, const std::string& path) {
  core::writeFileAtomically(path, [&](std::ostream& out) {
    out << "cell," << kConditionCsvHeader << ",method,n,n_failed";
    for (const Metric& m : kMetrics) out << "," << m.name << "_mean," << m.name << "_low," << m.name << "_high";
    out << ",vs_ls_median_abs_rel_err_win_rate,vs_ls_median_abs_rel_err_p_holm,vs_ls_torque_err_mean_win_rate,vs_ls_torque_err_mean_p_holm\n";
    for (const CellTables& c : cells) {
      const SweepCondition& k = layout.cells.at(static_cast<std::size_t>(c.cell));
      for (const MethodCell& m : c.methods) {
        out << c.cell << "," << conditionCsv(k) << "," << m.method << "," << m.n << "," << m.n_failed;
        for (const stats::ConfidenceInterval& ci : m.metrics) out << "," << csvNumber(ci.n ? ci.mean : kNaN) << "," << csvNumber(ci.low) << "," << csvNumber(ci.high);
        out << "," << csvNumber(m.rel.win_rate) << "," << csvNumber(m.rel.p_holm) << "," << csvNumber(m.torque.win_rate) << "," << csvNumber(m.torque.p_holm) << "\n";
      }
    }
  });
}

std::string meanAndCi(const stats::ConfidenceInterval& c, double scale, int digits) {
  if (c.n == 0) return "-";
  std::string s = fmt(scale * c.mean, digits);
  if (std::isfinite(c.low)) s += " [" + fmt(scale * c.low, digits) + ", " + fmt(scale * c.high, digits) + "]";
  return s;
}

void writeSummaryMd(const SweepLayout& layout, const std::vector<CellTables>& cells, const ParameterSets& sets, const std::string& path) {
  std::ostringstream md;
  const nlohmann::json& sw = layout.resolved.at("sweep");
  md << "# exoid sweep --model " << sw.at("model").get<std::string>() << "\n\n"
     << cells.size() << " cells x " << layout.seeds << " seeds; methods " ;
  for (std::size_t i = 0; i < layout.method_names.size(); ++i) md << (i ? ", " : "") << layout.method_names[i];
  md << "; master seed " << sw.at("master_seed").get<std::uint64_t>() << "; " << toolJson().dump() << ".\n\n"
     << "Each run: " << sw.at("design").get<std::string>() << ". Every score is against the simulation's truth "
     << "(summary.json explains each; config.json holds every setting). Values: mean over the seeds with an estimate "
     << "[95 % Student-t interval]; vs LS: win rate over the paired seeds (lower is a win) and Holm-adjusted Wilcoxon p.\n\n";
  for (const CellTables& c : cells) {
    const SweepCondition& k = layout.cells.at(static_cast<std::size_t>(c.cell));
    const ParameterSet set = sets.count(c.cell) ? sets.at(c.cell) : ParameterSet{};
    const std::vector<std::string>& names = set.names;
    const std::vector<double>& truth = set.truth;
    md << "## Cell " << c.cell << ": torque noise " << fmt(k.torque_noise_Nm, 4) << " N m, angle noise " << fmt(k.angle_noise_deg, 4)
       << " deg, quantisation " << fmt(k.quantisation_deg, 4) << " deg, vibration level " << fmt(k.vibration_level, 4) << ", encoder backlash "
       << fmt(k.encoder_backlash_deg, 4) << " deg, " << k.trajectories << " records\n\n"
       << "| method | runs (failed) | median abs error (%) | max abs error (%) | torque error vs truth (%) | validation RMS (N m) | "
          "vs LS: median error win rate, p Holm | vs LS: torque error win rate, p Holm |\n|---|---|---|---|---|---|---|---|\n";
    for (const MethodCell& m : c.methods) {
      md << "| " << m.method << " | " << m.n << " (" << m.n_failed << ") | " << meanAndCi(m.metrics[0], 100.0, 3) << " | "
         << meanAndCi(m.metrics[1], 100.0, 3) << " | " << meanAndCi(m.metrics[2], 100.0, 3) << " | " << meanAndCi(m.metrics[3], 1.0, 4) << " | ";
      if (m.method == "ls" || m.rel.n == 0) {
        md << "- | - |\n";
      } else {
        md << fmt(m.rel.win_rate, 3) << ", " << fmt(m.rel.p_holm, 3) << " | " << fmt(m.torque.win_rate, 3) << ", " << fmt(m.torque.p_holm, 3) << " |\n";
      }
    }
    md << "\nEach base parameter: median |error| (%) over the seeds (RMS of the absolute error where the truth is zero)";
    const MethodCell* ls = nullptr;
    for (const MethodCell& m : c.methods) {
      if (m.method == "ls") ls = &m;
    }
    if (ls) {
      md << "; LS z: RMS of error / LS's own standard error (1 when its standard errors are honest); LS coverage: seeds (%) whose "
            "estimate -+ 1.96 standard errors held the truth (nominal 95 %)";
    }
    md << ".\n\n| base parameter | truth |";
    for (const MethodCell& m : c.methods) md << " " << m.method << " |";
    if (ls) md << " LS z | LS coverage |";
    md << "\n|---|---|";
    for (std::size_t i = 0; i < c.methods.size() + (ls ? 2 : 0); ++i) md << "---|";
    md << "\n";
    for (std::size_t i = 0; i < names.size(); ++i) {
      md << "| " << names[i] << " | " << fmt(truth[i], 6) << " |";
      for (const MethodCell& m : c.methods) {
        md << " " << (hasRelativeError(truth, i) ? pct(m.abs_rel_median[i]) : (std::isfinite(m.abs_error_rms[i]) ? fmt(m.abs_error_rms[i], 3) + " abs" : "-"))
           << " |";
      }
      if (ls) {
        md << " " << (std::isfinite(ls->z_rms[i]) ? fmt(ls->z_rms[i], 3) : "-") << " | "
           << (ls->coverage[i].n ? fixed(100.0 * ls->coverage[i].share, 0) : std::string("-")) << " |";
      }
      md << "\n";
    }
    if (ls) {
      const std::string short_of = coverageShortfall(names, ls->coverage);
      md << "\n" << (short_of.empty() ? "LS covers every base parameter in at least " + fixed(100.0 * kCoverageShortfall, 0) + " % of the seeds.\n"
                                       : "LS short of " + fixed(100.0 * kCoverageShortfall, 0) + " % (share [Wilson 95 %], the mean error and the "
                                         "scatter in standard errors): " + short_of + "\n");
    }
    md << "\n";
  }
  md << "No figures: a chain sweep's output is these tables (runs.csv has every run).\n";
  core::writeFileAtomically(path, [&](std::ostream& o) { o << md.str(); });
}

}  // namespace chain_sweep_tables

void writeChainSweepTables(const SweepLayout& layout, const std::vector<nlohmann::json>& jobs, const std::string& dir) {
  chain_sweep_tables::ParameterSets sets;
  const std::vector<chain_sweep_tables::Row> rows = chain_sweep_tables::rowsOf(jobs, sets);
  chain_sweep_tables::writeRunsCsv(layout, rows, sets, jobs, dir + "/runs.csv");
  const std::vector<chain_sweep_tables::CellTables> cells = chain_sweep_tables::summarize(layout, rows, sets);
  writeJsonFile(dir + "/summary.json", chain_sweep_tables::summaryJson(layout, cells, sets));
  chain_sweep_tables::writeSummaryCsv(layout, cells, dir + "/summary.csv");
  chain_sweep_tables::writeSummaryMd(layout, cells, sets, dir + "/summary.md");
}

}  // namespace exoid::experiments
