#include "exoid/core/format.hpp"
#include "exoid/experiments/protocol/log_input.hpp"
#include "exoid/experiments/protocol/options.hpp"

#include "exoid/experiments/report/table.hpp"

#include <toml++/toml.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <stdexcept>

namespace exoid::experiments {

void addLogInputOptions(CLI::App& app, LogInputFlags& f) {
  const char* g = "Log format";
  app.add_option("--profile", f.profile,
                 "Log profile TOML: the log's column names, units, torque signs and model constants "
                 "(e.g. data/real/dfki_double_pendulum/profile.toml); flags below override it")
      ->check(CLI::ExistingFile)->group(g);
  app.add_option("--columns", f.columns, "Column map exoid_name=log_name,... (e.g. t=time,q_hip=pos_meas1,tau_hip=tau_meas1)")
      ->group(g);
  app.add_option("--time-unit", f.time_unit, "Unit of the time column: s (default), ms, us")
      ->check(CLI::IsMember({"s", "ms", "us"}))->group(g);
  app.add_option("--angle-unit", f.angle_unit, "Unit of angles (and their derivatives): rad (default), deg")
      ->check(CLI::IsMember({"rad", "deg"}))->group(g);
  app.add_option("--torque-sign", f.torque_sign, "Multiply each joint's torque by hip,knee (each 1 or -1)")->delimiter(',')->group(g);
  app.add_flag("--strict-sampling", f.strict_sampling,
               "Reject a log whose intervals differ from the median by > 0.1 % instead of resampling it")
      ->group(g);
  app.add_option("--max-gap-ms", f.max_gap_ms,
                 "Longest interval resampling bridges, ms (default: a tenth of the low-pass filter's period, 10 ms at 10 Hz)")
      ->check(positiveNumber())->group(g);
}

namespace {

// The names a column map may give a log's columns: what exoid reads for these joints.
std::set<std::string> exoidColumns(const std::vector<std::string>& joints) {
  std::set<std::string> out = {"t", "base_acc_x", "base_acc_z", "base_gyro_y"};
  for (const std::string& j : joints) {
    for (const char* prefix : {"q_", "tau_", "qd_", "qdd_"}) out.insert(prefix + j);
    out.insert("q_" + j + "_ref");
  }
  return out;
}

std::string unknownColumnMessage(const std::string& name, const std::set<std::string>& known) {
  const std::string list = core::joined(known);
  return "unknown exoid column '" + name + "' (a column map is exoid name = log name, e.g. t=time); exoid's names: " + list;
}

}  // namespace

LogInput readLogProfile(const std::string& path, const std::vector<std::string>& joints) {
  toml::table t;
  try {
    t = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    throw std::invalid_argument(path + ":" + core::toText(e.source().begin.line) + ":" +
                                core::toText(e.source().begin.column) + ": " + std::string(e.description()));
  }
  LogInput in;
  in.csv.joints = joints;
  in.profile = path;
  const auto at = [&](const toml::node& n) {
    return path + ":" + core::toText(n.source().begin.line) + ":" + core::toText(n.source().begin.column);
  };
  const auto text = [&](const toml::node& n, const std::string& key) {
    if (!n.is_string()) throw std::invalid_argument(at(n) + ": '" + key + "' must be a string");
    return *n.value<std::string>();
  };
  const auto number = [&](const toml::node& n, const std::string& key) {
    if (!(n.is_integer() || n.is_floating_point())) throw std::invalid_argument(at(n) + ": '" + key + "' must be a number");
    return *n.value<double>();
  };
  const std::set<std::string> kColumns = exoidColumns(joints);
  for (const auto& [section, node] : t) {
    const std::string s(section.str());
    const toml::table* tab = node.as_table();
    if (!tab) throw std::invalid_argument(at(node) + ": '" + s + "' must be a table ([" + s + "])");
    for (const auto& [k, v] : *tab) {
      const std::string key(k.str()), full = s + "." + key;
      try {
        if (s == "columns") {
          if (!kColumns.count(key)) throw std::invalid_argument(unknownColumnMessage(key, kColumns));
          in.csv.format.columns.emplace_back(key, text(v, full));
        } else if (full == "units.time") {
          in.csv.format.time_scale_s = ident::parseTimeUnit(text(v, full));
        } else if (full == "units.angle") {
          in.csv.format.angle_scale_rad = ident::parseAngleUnit(text(v, full));
          in.angle_unit_given = true;
        } else if (full.rfind("torque_sign.", 0) == 0 &&
                   std::find(in.csv.joints.begin(), in.csv.joints.end(), key) != in.csv.joints.end()) {
          const double sgn = number(v, full);
          if (std::abs(sgn) != 1.0) throw std::invalid_argument("must be 1 or -1");
          std::vector<double>& signs = in.csv.format.torque_sign;
          signs.resize(in.csv.joints.size(), 1.0);
          signs[static_cast<std::size_t>(std::find(in.csv.joints.begin(), in.csv.joints.end(), key) - in.csv.joints.begin())] = sgn;
        } else if (full == "model.thigh_length_m") {
          in.thigh_length_m = number(v, full);
          if (!(*in.thigh_length_m > 0)) throw std::invalid_argument("must be > 0 m");
        } else if (full == "model.gravity_mps2") {
          in.gravity_mps2 = number(v, full);
          if (!(*in.gravity_mps2 > 0)) throw std::invalid_argument("must be > 0 m/s^2");
        } else if (full == "sampling.max_gap_ms") {
          in.csv.max_gap_s = 1e-3 * number(v, full);
          if (!(in.csv.max_gap_s > 0)) throw std::invalid_argument("must be > 0 ms");
        } else {
          throw std::invalid_argument("unknown key; a profile has [columns] (exoid name = log name), [units] time, angle, "
                                      "[torque_sign] one per joint (hip, knee), [model] thigh_length_m, gravity_mps2, [sampling] max_gap_ms");
        }
      } catch (const std::invalid_argument& e) {
        if (std::string(e.what()).rfind(path, 0) == 0) throw;
        throw std::invalid_argument(at(v) + ": '" + full + "': " + e.what());
      }
    }
  }
  in.csv.format.validate();
  return in;
}

LogInput resolveLogInput(const LogInputFlags& f, double filter_cutoff_hz, const std::vector<std::string>& joints) {
  LogInput in;
  in.csv.joints = joints;
  if (!f.profile.empty()) in = readLogProfile(f.profile, joints);
  try {
    if (!f.columns.empty()) {
      // Flags override the profile name by name.
      const std::set<std::string> known = exoidColumns(joints);
      for (const auto& [ours, theirs] : ident::parseColumnMap(f.columns)) {
        if (!known.count(ours)) throw std::invalid_argument(unknownColumnMessage(ours, known));
        auto& cols = in.csv.format.columns;
        const std::string& name = ours;  // a lambda may not capture a structured binding in C++17 (clang)
        const auto it = std::find_if(cols.begin(), cols.end(), [&](const auto& p) { return p.first == name; });
        if (it == cols.end()) {
          cols.emplace_back(ours, theirs);
        } else {
          it->second = theirs;
        }
      }
    }
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("--columns: ") + e.what());
  }
  if (!f.time_unit.empty()) in.csv.format.time_scale_s = ident::parseTimeUnit(f.time_unit);
  if (!f.angle_unit.empty()) {
    in.csv.format.angle_scale_rad = ident::parseAngleUnit(f.angle_unit);
    in.angle_unit_given = true;
  }
  if (!f.torque_sign.empty()) {
    const bool ok = f.torque_sign.size() == in.csv.joints.size() &&
                    std::all_of(f.torque_sign.begin(), f.torque_sign.end(), [](double x) { return std::abs(x) == 1.0; });
    if (!ok) {
      std::string names;
      for (const std::string& j : in.csv.joints) names += (names.empty() ? "" : ",") + j;
      throw std::invalid_argument("--torque-sign: expected " + names + ", each 1 or -1");
    }
    in.csv.format.torque_sign = f.torque_sign;
  }
  if (f.strict_sampling) in.csv.sampling = ident::SamplingMode::kStrict;
  if (f.max_gap_ms) {
    in.csv.max_gap_s = 1e-3 * *f.max_gap_ms;
  } else if (in.csv.max_gap_s <= 0 && filter_cutoff_hz > 0) {
    in.csv.max_gap_s = 0.1 / filter_cutoff_hz;
  }
  try {
    in.csv.format.validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("--columns: ") + e.what());
  }
  return in;
}

namespace {
std::string gunzip(const std::string& path) {
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) throw ident::DatasetError(path, 0, 0, "cannot open file for reading");
  std::string out;
  char buf[1 << 16];
  int n = 0;
  while ((n = gzread(f, buf, sizeof buf)) > 0) out.append(buf, static_cast<std::size_t>(n));
  int err = 0;
  const std::string msg = n < 0 ? gzerror(f, &err) : "";
  gzclose(f);
  if (n < 0) throw ident::DatasetError(path, 0, 0, "not a readable gzip file: " + msg);
  return out;
}
}  // namespace

ident::Dataset readLog(const std::string& path, const LogInput& in) {
  ident::Dataset d = endsWith(path, ".gz") ? ident::parseDatasetText(gunzip(path), path, in.csv) : ident::readDatasetCsv(path, in.csv);
  if (!in.angle_unit_given) {
    const std::string hint = ident::angleUnitHint(d);
    if (!hint.empty()) throw std::invalid_argument(path + ": " + hint);
  }
  if (in.check_record) in.check_record(path, d);
  return d;
}

std::string timeUnitHint(const ident::Dataset& d) {
  if (!(d.sampling.median_dt_s > 0.05)) return "";
  return " (the time column's median interval is " + fmt(d.sampling.median_dt_s, 4) +
         " s: if its unit is ms or us, say so with --time-unit or the profile's [units] time)";
}

std::string samplingSummary(const ident::Dataset& d, const ident::CsvReadOptions& o) {
  const ident::SamplingReport& r = d.sampling;
  std::string s = fmt(1e3 * r.median_dt_s, 4) + " ms median interval";
  if (r.intervals_off == 0) return "uniform, " + s;
  s += ", " + core::toText(r.intervals_off) + " of " + core::toText(r.rows_read - 1) + " intervals off by > " +
       fmt(100.0 * o.dt_rel_tolerance) + " % (" + fmt(1e3 * r.min_dt_s, 4) + " to " + fmt(1e3 * r.max_dt_s, 4) +
       " ms, the longest ending at line " + core::toText(r.max_dt_line) + ")";
  if (r.resampled) s += ": resampled to " + core::toText(d.size()) + " rows on a uniform grid (cubic Hermite)";
  return s;
}

nlohmann::json samplingJson(const ident::Dataset& d) {
  const ident::SamplingReport& r = d.sampling;
  return {{"rows_read", r.rows_read}, {"median_dt_s", r.median_dt_s}, {"min_dt_s", r.min_dt_s}, {"max_dt_s", r.max_dt_s},
          {"intervals_off", r.intervals_off}, {"resampled", r.resampled}, {"rows_used", d.size()}};
}

}  // namespace exoid::experiments
