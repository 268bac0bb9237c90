#include "exoid/ident/io/dataset.hpp"

#include "exoid/core/atomic_file.hpp"
#include "exoid/core/format.hpp"
#include "exoid/core/parallel_for.hpp"

#include "csv_lines.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <iterator>
#include <limits>
#include <string_view>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

namespace exoid::ident {

namespace {

std::string where(const std::string& source, long line, long column) {
  std::string s = source;
  if (line > 0) s += ":" + core::toText(line);
  if (column > 0) s += ":" + core::toText(column);
  return s;
}

// The required columns of a robot with these joints: t, q_<joint>..., tau_<joint>...
std::vector<std::string> requiredColumns(const std::vector<std::string>& joints) {
  std::vector<std::string> out = {"t"};
  for (const char* prefix : {"q_", "tau_"}) {
    for (const std::string& j : joints) out.push_back(prefix + j);
  }
  return out;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

double median(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

DatasetError::DatasetError(std::string source, long line, long column, const std::string& what)
    : std::runtime_error(where(source, line, column) + ": " + what),
      source_(std::move(source)),
      line_(line),
      column_(column) {}

void Dataset::requireJoints(const std::vector<std::string>& expected, const std::string& who) const {
  if (joints != expected) {
    throw std::invalid_argument(who + " needs a record of the joints " + core::joined(expected, ", ") + "; this one has " +
                                core::joined(joints, ", ") + " (pass the robot's model, --model)");
  }
}

double Dataset::sampleInterval_s() const {
  if (size() < 2) throw std::invalid_argument("dataset: need >= 2 samples for a sampling interval");
  return (t_s[size() - 1] - t_s[0]) / static_cast<double>(size() - 1);
}

std::optional<std::string> Dataset::metadata(const std::string& key) const {
  for (const std::string& c : comments) {
    const std::string line = trim(c);
    const auto colon = line.find(':');
    if (colon != std::string::npos && trim(line.substr(0, colon)) == key) {
      return trim(line.substr(colon + 1));
    }
  }
  return std::nullopt;
}

Dataset Dataset::window(Eigen::Index from, Eigen::Index n) const {
  if (from < 0 || n < 0 || from + n > size()) {
    throw std::invalid_argument("Dataset::window: rows [" + core::toText(from) + ", " + core::toText(from + n) + ") of " + core::toText(size()));
  }
  const Dataset& d = *this;
  Dataset w;
  w.comments = d.comments;
  w.joints = d.joints;
  w.t_s = d.t_s.segment(from, n);
  w.q_rad = d.q_rad.middleRows(from, n);
  w.tau_Nm = d.tau_Nm.middleRows(from, n);
  if (d.qd_radps) w.qd_radps = d.qd_radps->middleRows(from, n);
  if (d.qdd_radps2) w.qdd_radps2 = d.qdd_radps2->middleRows(from, n);
  w.extra_names = d.extra_names;
  // No extra columns: no data pointer to offset (a block of it is undefined behaviour, UBSan says).
  if (d.extra.cols() > 0) {
    w.extra = d.extra.middleRows(from, n);
  } else {
    w.extra.resize(n, 0);
  }
  w.text_columns = d.text_columns;
  w.sampling = d.sampling;
  return w;
}

Eigen::VectorXd Dataset::extraColumn(const std::string& name) const {
  const auto it = std::find(extra_names.begin(), extra_names.end(), name);
  if (it == extra_names.end()) throw std::invalid_argument("dataset has no column '" + name + "'");
  return extra.col(it - extra_names.begin());
}

namespace {

bool isKnown(const std::string& name, const std::vector<std::string>& joints) {
  if (name == "t") return true;
  for (const std::string& j : joints) {
    for (const char* prefix : {"q_", "tau_", "qd_", "qdd_"}) {
      if (name == prefix + j) return true;
    }
  }
  return false;
}

// A number cell: blanks around it allowed, a leading '+' too; nothing else.
bool parseNumber(std::string_view cell, double& v) {
  const auto blank = [](char ch) { return ch == ' ' || ch == '\t'; };
  if (cell.empty() || blank(cell.front()) || blank(cell.back())) cell = csv::trimBlanks(cell);  // most cells have none
  if (!cell.empty() && cell[0] == '+') cell.remove_prefix(1);
  if (cell.empty()) return false;
  const auto r = std::from_chars(cell.data(), cell.data() + cell.size(), v);
  return r.ec == std::errc() && r.ptr == cell.data() + cell.size();
}

}  // namespace

void LogFormat::validate() const {
  if (!(time_scale_s > 0 && std::isfinite(time_scale_s))) throw std::invalid_argument("log format: time unit must be > 0 s");
  if (!(angle_scale_rad > 0 && std::isfinite(angle_scale_rad))) throw std::invalid_argument("log format: angle unit must be > 0 rad");
  for (double sign : torque_sign) {
    if (std::abs(sign) != 1.0) throw std::invalid_argument("log format: torque signs must be +1 or -1");
  }
  std::map<std::string, int> seen;
  for (const auto& [ours, theirs] : columns) {
    if (ours.empty() || theirs.empty()) throw std::invalid_argument("log format: empty name in the column map");
    if (seen[ours]++) throw std::invalid_argument("log format: '" + ours + "' is mapped twice");
  }
}

std::vector<std::pair<std::string, std::string>> parseColumnMap(const std::string& text) {
  std::vector<std::pair<std::string, std::string>> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    const auto comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const auto eq = item.find('=');
    const std::string ours = trim(item.substr(0, eq)), theirs = eq == std::string::npos ? "" : trim(item.substr(eq + 1));
    if (eq == std::string::npos || ours.empty() || theirs.empty()) {
      throw std::invalid_argument("column map: expected exoid_name=log_name pairs separated by commas (e.g. "
                                  "t=time,q_hip=pos_meas1), got '" + item + "'");
    }
    out.emplace_back(ours, theirs);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

double parseTimeUnit(const std::string& unit) {
  if (unit == "s") return 1.0;
  if (unit == "ms") return 1e-3;
  if (unit == "us") return 1e-6;
  throw std::invalid_argument("time unit '" + unit + "': expected s, ms or us");
}

double parseAngleUnit(const std::string& unit) {
  if (unit == "rad") return 1.0;
  if (unit == "deg") return M_PI / 180.0;
  throw std::invalid_argument("angle unit '" + unit + "': expected rad or deg");
}

namespace {

// Largest magnitude a known column may hold, in any of the units the reader accepts (time in s
// down to ns, angles in rad or deg): far beyond any leg, far below what overflows the arithmetic
// (a torque cell of 1e308 used to come back as Mxt = 1e302, "converged").
double physicalBound(const std::string& column) {
  if (column == "t") return 1e15;                   // 11 days in ns
  if (column.rfind("qdd_", 0) == 0) return 1e8;     // rad/s^2 or deg/s^2
  if (column.rfind("qd_", 0) == 0) return 1e6;      // rad/s or deg/s
  if (column.rfind("q_", 0) == 0) return 1e5;       // rad or deg
  return 1e6;                                       // torques, N m
}

// The reader proper, one step per member: the first pass (comments, the header: names, column
// map, required columns; the data rows counted and cut into ranges), the allocation, the data
// rows of each range (parsed in parallel, each into its own rows), then text columns, units and
// the time axis.
class LogParser {
 public:
  LogParser(const std::string& source, const CsvReadOptions& options) : source_(source), options_(options) {}

  /// A row whose file line is not the previous row's + 1 (the first, and any after a comment or
  /// a blank line): every row's line follows from these.
  struct LineBreak {
    Eigen::Index row = 0;
    long line = 0;
  };

  /// A range of data lines parsed on its own: from the line at `offset` (its file line number),
  /// the data rows first_row, ... up to the next range's.
  struct Range {
    std::int64_t offset = 0;
    long line_number = 0;
    Eigen::Index first_row = 0;
  };

  /// The lines up to the header: comments, then the header itself. False once it is read.
  bool beforeData(const csv::Line& line) {
    if (header_line_ != 0) return false;
    if (line.comment) {
      d_.comments.emplace_back(line.text);
    } else {
      header(line);
    }
    return true;
  }

  /// The data rows' ranges, counted (rows in all), and the comments among them in file order.
  void setRanges(std::vector<Range> ranges, Eigen::Index rows, const std::vector<std::string>& comments) {
    ranges_ = std::move(ranges);
    rows_ = rows;
    d_.comments.insert(d_.comments.end(), comments.begin(), comments.end());
    if (header_line_ != 0) allocateColumns();
  }

  const std::vector<Range>& ranges() const { return ranges_; }

  /// Where range k's parse stands: its next row, where each column goes (a text column found in
  /// it becomes nullptr there), and the rows whose file line is not the previous row's + 1.
  struct RangeState {
    Eigen::Index row = 0;
    std::vector<double*> target;
    std::vector<LineBreak> breaks;
  };
  RangeState rangeStart(std::size_t k) const { return {ranges_[k].first_row, target_, {}}; }

  /// A line of range k (comments were read by the scan): its data row, written into its own row.
  void parseRange(std::size_t k, const csv::Line& line, RangeState& state) const {
    if (line.comment) return;
    if (state.row >= rangeEnd(k)) changedWhileRead();
    if (state.breaks.empty() || line.number != state.breaks.back().line + (state.row - state.breaks.back().row)) {
      state.breaks.push_back({state.row, line.number});
    }
    dataRow(line, state.row++, state.target);
  }
  Eigen::Index rangeEnd(std::size_t k) const { return k + 1 < ranges_.size() ? ranges_[k + 1].first_row : rows_; }
  [[noreturn]] void changedWhileRead() const {
    throw DatasetError(source_, 0, 0, "the file changed while it was read (" + core::toText(rows_) +
                                          " data rows in the first pass, another count in the second): read a finished log");
  }

  /// After every range: a column is text when any range found a non-number in it.
  void merge(const std::vector<RangeState>& states) {
    for (const RangeState& r : states) {
      for (std::size_t c = 0; c < ncol_; ++c) {
        if (!r.target[c]) target_[c] = nullptr;
      }
      breaks_.insert(breaks_.end(), r.breaks.begin(), r.breaks.end());
    }
    row_ = rows_;
  }

  Dataset finish() {
    if (header_line_ == 0) {
      throw DatasetError(source_, 0, 0, "empty file: expected a header line '" + core::joined(requiredColumns(options_.joints), ",") +
                                            "' followed by data rows");
    }
    const long min_rows = std::max(options_.min_rows, 2L);  // a time axis needs an interval
    if (row_ < min_rows) {
      throw DatasetError(source_, 0, 0, "expected at least " + core::toText(min_rows) + " data rows, got " + core::toText(row_));
    }
    dropTextColumns();
    applyUnits();
    return timeAxis();
  }

 private:
  void header(const csv::Line& line) {
    header_line_ = line.number;
    readNames(line);
    mapColumns();
    indexColumns();
  }

  void readNames(const csv::Line& line) {
    for (std::string_view c : line.cells) names_.emplace_back(csv::trimBlanks(c));
    // A UTF-8 byte-order mark (spreadsheet exports) is not part of the first name.
    if (!names_.empty() && names_.front().rfind("\xEF\xBB\xBF", 0) == 0) names_.front().erase(0, 3);
    // Another separator: say so, instead of "missing required column 't'" for a one-column header.
    if (names_.size() == 1) {
      for (const auto& [sep, what] : {std::pair<char, const char*>{'\t', "tabs"}, {';', "semicolons"}, {' ', "spaces"}}) {
        if (names_.front().find(sep) != std::string::npos) {
          throw DatasetError(source_, header_line_, 0,
                             std::string("the header has no commas but is separated by ") + what +
                                 ": exoid reads comma-separated files (convert it, e.g. tr '" + (sep == '\t' ? "\\t" : std::string(1, sep)) +
                                 "' ',' < in > out.csv, minding decimal commas)");
        }
      }
    }
    if (names_.size() > 1 && names_.back().empty()) {  // "a,b,c," on every line
      names_.pop_back();
      trailing_comma_ = true;
    }
  }

  // The log's names -> exoid's, as the format maps them.
  void mapColumns() {
    const std::vector<std::string> file_names = names_;  // the header as written, for messages
    for (const auto& [ours, theirs] : options_.format.columns) {
      const auto it = std::find(names_.begin(), names_.end(), theirs);
      if (it == names_.end()) {
        throw DatasetError(source_, header_line_, 0,
                           "column '" + theirs + "' (mapped to " + ours + ") is not in the header; it has: " + core::joined(file_names));
      }
      if (ours != theirs && std::find(names_.begin(), names_.end(), ours) != names_.end()) {
        throw DatasetError(source_, header_line_, static_cast<long>(std::find(names_.begin(), names_.end(), ours) - names_.begin()) + 1,
                           "column '" + ours + "' is in the header and also mapped from '" + theirs + "': which one is meant?");
      }
      *it = ours;
    }
  }

  void indexColumns() {
    for (std::size_t c = 0; c < names_.size(); ++c) {
      const long col = static_cast<long>(c) + 1;
      if (names_[c].empty()) throw DatasetError(source_, header_line_, col, "empty column name in header");
      if (!index_.emplace(names_[c], static_cast<long>(c)).second) {
        throw DatasetError(source_, header_line_, col, "duplicate column '" + names_[c] + "'");
      }
    }
    const std::vector<std::string> required = requiredColumns(options_.joints);
    for (const std::string& r : required) {
      if (!index_.count(r)) {
        throw DatasetError(source_, header_line_, 0,
                           "missing required column '" + r + "' (required: " + core::joined(required, ",") +
                               "; a log with its own names needs a column map, e.g. --columns t=time,q_" + options_.joints.front() +
                               "=pos_meas1,...); the header has: " + core::joined(names_));
      }
    }
    // A joint the model does not have (q_X and tau_X, X not one of its joints nor a variant
    // such as hip_true): a record of another robot, which the model would fit silently wrong.
    for (const auto& [name, col] : index_) {
      if (name.rfind("q_", 0) != 0) continue;
      const std::string joint = name.substr(2);
      if (!index_.count("tau_" + joint) || isKnown(name, options_.joints)) continue;
      bool variant = false;
      for (const std::string& j : options_.joints) variant = variant || joint.rfind(j + "_", 0) == 0;
      if (!variant) {
        throw DatasetError(source_, header_line_, col + 1,
                           "the record has a joint '" + joint + "' (q_" + joint + ", tau_" + joint + ") that the model (" +
                               core::joined(options_.joints, ", ") + ") does not: it is another robot's record; give its model (--model)");
      }
    }
    // Derivative columns: all joints or none.
    for (const char* prefix : {"qd_", "qdd_"}) {
      long present = 0;
      for (const std::string& j : options_.joints) present += static_cast<long>(index_.count(prefix + j));
      if (present == 0 || present == static_cast<long>(options_.joints.size())) continue;
      for (const std::string& j : options_.joints) {
        if (!index_.count(prefix + j)) {
          throw DatasetError(source_, header_line_, 0,
                             std::string("missing column '") + prefix + j + "': derivative columns come for every joint (" +
                                 core::joined(options_.joints, ", ") + ") or for none");
        }
      }
    }
  }

  // Every column at its final size (the first pass counted the rows): parsed straight into place.
  void allocateColumns() {
    ncol_ = names_.size();
    const Eigen::Index n = std::max<Eigen::Index>(rows_, 0);
    d_.t_s.resize(n);
    const auto dof = static_cast<Eigen::Index>(options_.joints.size());
    d_.joints = options_.joints;
    d_.q_rad.resize(n, dof);
    d_.tau_Nm.resize(n, dof);
    const std::string& first = options_.joints.front();
    if (index_.count("qd_" + first)) d_.qd_radps = Eigen::MatrixXd(n, dof);
    if (index_.count("qdd_" + first)) d_.qdd_radps2 = Eigen::MatrixXd(n, dof);
    for (std::size_t c = 0; c < ncol_; ++c) {
      if (!isKnown(names_[c], options_.joints)) d_.extra_names.push_back(names_[c]);
    }
    d_.extra.resize(n, static_cast<Eigen::Index>(d_.extra_names.size()));
    std::map<std::string, double*> where = {{"t", d_.t_s.data()}};
    for (Eigen::Index j = 0; j < dof; ++j) {
      const std::string& name = options_.joints[static_cast<std::size_t>(j)];
      where["q_" + name] = d_.q_rad.col(j).data();
      where["tau_" + name] = d_.tau_Nm.col(j).data();
      if (d_.qd_radps) where["qd_" + name] = d_.qd_radps->col(j).data();
      if (d_.qdd_radps2) where["qdd_" + name] = d_.qdd_radps2->col(j).data();
    }
    for (std::size_t k = 0; k < d_.extra_names.size(); ++k) where[d_.extra_names[k]] = d_.extra.col(static_cast<Eigen::Index>(k)).data();
    for (std::size_t c = 0; c < ncol_; ++c) {
      target_.push_back(where.at(names_[c]));
      known_.push_back(isKnown(names_[c], options_.joints) ? 1 : 0);
      bound_.push_back(physicalBound(names_[c]));  // once per column, not per cell (the hot loop)
    }
  }

  void dataRow(const csv::Line& line, Eigen::Index row, std::vector<double*>& target) const {
    std::size_t cells = line.cells.size();
    if (trailing_comma_ && cells == ncol_ + 1 && csv::trimBlanks(line.cells.back()).empty()) --cells;
    if (cells != ncol_) {
      throw DatasetError(source_, line.number, 0,
                         "expected " + core::toText(ncol_) + " cells as in the header, got " + core::toText(cells));
    }
    for (std::size_t c = 0; c < ncol_; ++c) {
      if (!target[c]) continue;
      double v = 0.0;
      const bool ok = parseNumber(line.cells[c], v);
      const long col = static_cast<long>(c) + 1;
      if (!known_[c]) {
        if (!ok || !std::isfinite(v)) target[c] = nullptr;  // an extra column that is not a number: dropped
        if (!target[c]) continue;
      } else if (!ok || !std::isfinite(v)) {
        throw DatasetError(source_, line.number, col,
                           "column '" + names_[c] + "': expected a " + std::string(ok ? "finite " : "") + "number, got '" +
                               std::string(csv::trimBlanks(line.cells[c])) + "'");
      } else if (std::abs(v) > bound_[c]) {
        throw DatasetError(source_, line.number, col,
                           "column '" + names_[c] + "': " + std::string(csv::trimBlanks(line.cells[c])) +
                               " is not a physical value (|" + names_[c] + "| <= " + core::formatNumber(bound_[c]) +
                               " in the log's units)");
      }
      target[c][row] = v;
    }
  }

  // Extra columns found to hold text: dropped from the numbers, named in text_columns.
  void dropTextColumns() {
    std::vector<std::string> numeric_names;
    std::vector<Eigen::Index> keep;
    for (std::size_t c = 0, k = 0; c < ncol_; ++c) {
      if (known_[c]) continue;
      if (target_[c]) {
        numeric_names.push_back(names_[c]);
        keep.push_back(static_cast<Eigen::Index>(k));
      } else {
        d_.text_columns.push_back(names_[c]);
      }
      ++k;
    }
    if (d_.text_columns.empty()) return;
    Eigen::MatrixXd kept(row_, static_cast<Eigen::Index>(keep.size()));
    for (std::size_t k = 0; k < keep.size(); ++k) kept.col(static_cast<Eigen::Index>(k)) = d_.extra.col(keep[k]);
    d_.extra = std::move(kept);
    d_.extra_names = numeric_names;
  }

  // Units and signs, in place.
  void applyUnits() {
    const LogFormat& f = options_.format;
    if (f.time_scale_s != 1.0) d_.t_s *= f.time_scale_s;
    if (f.angle_scale_rad != 1.0) {
      d_.q_rad *= f.angle_scale_rad;
      if (d_.qd_radps) *d_.qd_radps *= f.angle_scale_rad;
      if (d_.qdd_radps2) *d_.qdd_radps2 *= f.angle_scale_rad;
    }
    for (std::size_t j = 0; j < f.torque_sign.size(); ++j) d_.tau_Nm.col(static_cast<Eigen::Index>(j)) *= f.torque_sign[j];
  }

  // Time strictly increasing; uniform, or resampled onto a uniform grid (strict: refused).
  Dataset timeAxis() {
    checkIncreasing();
    const auto dt = [&](Eigen::Index i) { return d_.t_s[i + 1] - d_.t_s[i]; };  // interval i: rows i, i + 1
    const Eigen::Index intervals = row_ - 1;
    SamplingReport& rep = d_.sampling;
    rep.rows_read = static_cast<long>(row_);
    rep.median_dt_s = medianInterval();
    Eigen::Index longest = 0;
    rep.min_dt_s = rep.max_dt_s = dt(0);
    for (Eigen::Index i = 1; i < intervals; ++i) {
      rep.min_dt_s = std::min(rep.min_dt_s, dt(i));
      if (dt(i) > rep.max_dt_s) {  // the first longest
        rep.max_dt_s = dt(i);
        longest = i;
      }
    }
    rep.max_dt_line = lineOf(longest + 1);
    Eigen::Index first_off = -1;
    for (Eigen::Index i = 0; i < intervals; ++i) {
      if (std::abs(dt(i) - rep.median_dt_s) > options_.dt_rel_tolerance * rep.median_dt_s) {
        ++rep.intervals_off;
        if (first_off < 0) first_off = i;
      }
    }
    if (rep.intervals_off == 0) return std::move(d_);
    if (options_.sampling == SamplingMode::kStrict) {
      char buf[240];
      std::snprintf(buf, sizeof buf,
                    "sampling is not uniform: interval %.9g s differs from the median %.9g s by more than %.3g %% (%ld "
                    "such intervals; without strict sampling the record would be resampled)",
                    dt(first_off), rep.median_dt_s, 100.0 * options_.dt_rel_tolerance, rep.intervals_off);
      throw DatasetError(source_, lineOf(first_off + 1), timeColumn(), buf);
    }
    checkGap(longest);
    const SamplingReport kept = rep;
    Dataset r = resampleUniform(d_, rep.median_dt_s);
    r.sampling = kept;
    r.sampling.resampled = true;
    if (r.size() < options_.min_rows) {
      throw DatasetError(source_, 0, 0, "expected at least " + core::toText(options_.min_rows) +
                                            " rows after resampling, got " + core::toText(r.size()));
    }
    return r;
  }

  void checkIncreasing() const {
    for (Eigen::Index i = 1; i < row_; ++i) {
      if (!(d_.t_s[i] - d_.t_s[i - 1] > 0.0)) {
        throw DatasetError(source_, lineOf(i), timeColumn(),
                           "time must be strictly increasing: t = " + core::toText(d_.t_s[i]) +
                               " s after t = " + core::toText(d_.t_s[i - 1]) + " s");
      }
    }
  }

  double medianInterval() const {
    std::vector<double> dts(static_cast<std::size_t>(row_ - 1));
    for (Eigen::Index i = 1; i < row_; ++i) dts[static_cast<std::size_t>(i - 1)] = d_.t_s[i] - d_.t_s[i - 1];
    return median(std::move(dts));
  }

  // The file line of a data row.
  long lineOf(Eigen::Index row) const {
    const auto after = std::upper_bound(breaks_.begin(), breaks_.end(), row,
                                        [](Eigen::Index r, const LineBreak& b) { return r < b.row; });
    const LineBreak& b = *std::prev(after);  // breaks_ starts at row 0
    return b.line + static_cast<long>(row - b.row);
  }

  // Resampling bridges short gaps only: a longer one is a break in the log. k: the longest interval.
  void checkGap(Eigen::Index k) const {
    const SamplingReport& rep = d_.sampling;
    const double max_gap = options_.max_gap_s > 0 ? options_.max_gap_s : 10.0 * rep.median_dt_s;
    const double gap = d_.t_s[k + 1] - d_.t_s[k];
    if (gap <= max_gap) return;
    char buf[300];
    std::snprintf(buf, sizeof buf,
                  "a gap of %.6g s between lines %ld and %ld (t = %.6g .. %.6g s) is longer than the %.6g s resampling "
                  "bridges (the median interval is %.6g s): split the log there, or raise the limit",
                  gap, lineOf(k), lineOf(k + 1), d_.t_s[k], d_.t_s[k + 1], max_gap, rep.median_dt_s);
    throw DatasetError(source_, lineOf(k + 1), timeColumn(), buf);
  }

  long timeColumn() const { return index_.at("t") + 1; }

  const std::string& source_;
  const CsvReadOptions& options_;
  Eigen::Index rows_ = 0;  // data lines the first pass counted
  std::vector<Range> ranges_;
  Dataset d_;
  std::vector<std::string> names_;
  long header_line_ = 0;
  bool trailing_comma_ = false;
  std::map<std::string, long> index_;  // exoid name -> 0-based column
  std::vector<double*> target_;        // per column: where its values go (nullptr: a text column)
  std::vector<char> known_;  // per column: one of exoid's (char, not a bit: read per cell)
  std::vector<double> bound_;           // per column: the largest physical magnitude
  std::vector<LineBreak> breaks_;  // sorted by row, the first row's included
  std::size_t ncol_ = 0;
  Eigen::Index row_ = 0;
};

// The first line start at or after byte `from` of a text of total_bytes whose lines end in `eol`:
// just after the first line end at or after from - 1 (in a CR file, a CR LF pair is one end), or
// total_bytes.
template <typename Open>
std::int64_t lineStartFrom(Open& open, std::int64_t from, std::int64_t total_bytes, char eol) {
  const auto scan_bytes = static_cast<std::size_t>(std::min<std::int64_t>(std::int64_t(64) << 10, total_bytes - from + 2));
  std::unique_ptr<char[]> chunk(new char[scan_bytes]);
  auto read = open(from - 1, -1);
  std::int64_t at = from - 1;  // the text's offset of chunk[0]
  bool after_cr = false;       // CR file: the last chunk ended on a line's CR
  while (const std::size_t n = read(chunk.get(), scan_bytes)) {
    if (after_cr) return chunk[0] == '\n' ? at + 1 : at;
    if (const void* hit = std::memchr(chunk.get(), eol, n)) {
      const auto e = static_cast<std::size_t>(static_cast<const char*>(hit) - chunk.get());
      const std::int64_t start = at + static_cast<std::int64_t>(e) + 1;
      if (eol == '\n') return start;
      if (e + 1 < n) return chunk[e + 1] == '\n' ? start + 1 : start;
      after_cr = true;
      at = start;
      continue;
    }
    at += static_cast<std::int64_t>(n);
  }
  return after_cr ? at : total_bytes;
}

// `open(offset, end)` returns a chunk reader (read(dst, max) -> bytes, 0 at the end) of the text's
// bytes [offset, end), end < 0 for all the rest; `eol` is its line end when known (0: from the
// first chunk). The header is read first; the data rows are cut into ranges at line starts, each
// range counted, then parsed into its own rows, on up to options.threads threads (the same
// dataset whatever the number and the range size; an error is the first in the file, as a single
// pass would report it).
template <typename Open>
Dataset parseLog(Open&& open, std::int64_t total_bytes, const std::string& source, const CsvReadOptions& options,
                 char eol_known = 0) {
  try {
    options.format.validate();
    if (options.joints.empty()) throw std::invalid_argument("dataset: the model names no joints");
    for (std::size_t j = 0; j < options.joints.size(); ++j) {
      if (options.joints[j].empty() || std::count(options.joints.begin(), options.joints.end(), options.joints[j]) > 1) {
        throw std::invalid_argument("dataset: joint names must be distinct and non-empty, got " + core::joined(options.joints, ", "));
      }
    }
    if (!options.format.torque_sign.empty() && options.format.torque_sign.size() != options.joints.size()) {
      throw std::invalid_argument("log format: " + core::toText(options.format.torque_sign.size()) + " torque signs for " +
                                  core::toText(options.joints.size()) + " joints (" + core::joined(options.joints, ", ") + ")");
    }
    if (options.threads < 0) throw std::invalid_argument("'threads' must be >= 0 (0 = the machine's cores), got " + core::toText(options.threads));
  } catch (const std::invalid_argument& e) {
    throw DatasetError(source, 0, 0, e.what());
  }
  LogParser parser(source, options);
  try {
    // The header, and where the data start (the line after it).
    csv::LineSplitter splitter;
    std::int64_t data_offset = -1;
    long data_line = 0;
    splitter.run(open(0, -1), [&](const csv::Line& line) {
      if (parser.beforeData(line)) return;
      data_offset = line.offset;
      data_line = line.number;
      splitter.stop();
    }, true, csv::Start{1, eol_known, true, static_cast<std::size_t>(total_bytes)});
    const char eol = splitter.eol();
    // The data cut into pieces of about range_bytes at line starts; each piece's lines counted on
    // its own (in parallel), then numbered in order.
    struct Piece {
      std::int64_t begin = 0, end = 0;
      long lines = 0;
      Eigen::Index rows = 0;
      std::vector<std::string> comments;
    };
    std::vector<Piece> pieces;
    if (data_offset >= 0) {
      const std::size_t step = std::max<std::size_t>(options.range_bytes, 1);
      for (std::int64_t begin = data_offset; begin < total_bytes;) {
        const bool last = step >= static_cast<std::uint64_t>(total_bytes - begin);  // unsigned: any range_bytes
        const std::int64_t end = last ? total_bytes : lineStartFrom(open, begin + static_cast<std::int64_t>(step), total_bytes, eol);
        pieces.push_back({begin, end, 0, 0, {}});
        begin = end;
      }
    }
    core::parallelFor(pieces.size(), options.threads, [&](std::size_t k) {
      Piece& p = pieces[k];
      csv::LineSplitter counter;
      counter.run(open(p.begin, p.end), [&](const csv::Line& line) {
        if (line.comment) {
          p.comments.emplace_back(line.text);
        } else {
          ++p.rows;
        }
      }, false, csv::Start{1, eol, false, static_cast<std::size_t>(p.end - p.begin)});
      p.lines = counter.lines();
    });
    std::vector<LogParser::Range> ranges;
    std::vector<std::string> comments;
    Eigen::Index rows = 0;
    long line_number = data_line;
    for (Piece& p : pieces) {
      ranges.push_back({p.begin, line_number, rows});
      rows += p.rows;
      line_number += p.lines;
      comments.insert(comments.end(), std::make_move_iterator(p.comments.begin()), std::make_move_iterator(p.comments.end()));
    }
    parser.setRanges(std::move(ranges), rows, comments);
    // The data rows, each range into its own rows (in parallel).
    std::vector<LogParser::RangeState> states(pieces.size());
    core::parallelFor(pieces.size(), options.threads, [&](std::size_t k) {
      const LogParser::Range& r = parser.ranges()[k];
      LogParser::RangeState& state = states[k];
      state = parser.rangeStart(k);
      csv::LineSplitter range_splitter;
      range_splitter.run(open(r.offset, pieces[k].end), [&](const csv::Line& line) { parser.parseRange(k, line, state); },
                         true, csv::Start{r.line_number, eol, false, static_cast<std::size_t>(pieces[k].end - r.offset)});
      if (state.row != parser.rangeEnd(k)) parser.changedWhileRead();
    });
    parser.merge(states);
  } catch (const csv::SyntaxError& e) {
    throw DatasetError(source, e.line, e.column, e.what);
  }
  return parser.finish();
}

}  // namespace

namespace {
// A text's line end as one pass over all of it decides: LF when it has one (after a byte-order
// mark), else CR, else none.
char textLineEnd(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  if (text.find('\n') != std::string_view::npos) return '\n';
  return text.find('\r') != std::string_view::npos ? '\r' : 0;
}
}  // namespace

Dataset parseDatasetText(std::string_view text, const std::string& source, const CsvReadOptions& options) {
  return parseLog(
      [text](std::int64_t offset, std::int64_t end) {
        const auto from = static_cast<std::size_t>(offset);
        std::string_view left = text.substr(from, end < 0 ? std::string_view::npos : static_cast<std::size_t>(end - offset));
        return [left](char* dst, std::size_t max) mutable {
          const std::size_t n = std::min(max, left.size());
          if (n > 0) std::memcpy(dst, left.data(), n);  // an empty view's data() may be null
          left.remove_prefix(n);
          return n;
        };
      },
      static_cast<std::int64_t>(text.size()), source, options, textLineEnd(text));
}

Dataset parseDatasetCsv(std::istream& in, const std::string& source, const CsvReadOptions& options) {
  std::string text;
  try {
    std::unique_ptr<char[]> chunk(new char[csv::kChunkBytes]);
    while (const std::size_t n = csv::readChunk(in, chunk.get(), csv::kChunkBytes)) text.append(chunk.get(), n);
  } catch (const std::runtime_error& e) {
    throw DatasetError(source, 0, 0, std::string(e.what()) + " after " + core::toText(text.size()) + " bytes");
  }
  return parseDatasetText(text, source, options);
}

Dataset readDatasetCsv(const std::string& path, const CsvReadOptions& options) {
  const auto open = [&path](std::int64_t offset, std::int64_t end) {
    auto in = std::make_shared<std::ifstream>(path, std::ios::binary);
    if (!*in) throw DatasetError(path, 0, 0, "cannot open file for reading");
    if (offset > 0 && !in->seekg(offset)) throw DatasetError(path, 0, 0, "cannot seek to byte " + core::toText(offset));
    // Bytes left to read: the range's, or all (the file's end).
    auto left = end < 0 ? std::numeric_limits<std::size_t>::max() : static_cast<std::size_t>(end - offset);
    return [in, path, left](char* dst, std::size_t max) mutable {
      try {
        const std::size_t n = csv::readChunk(*in, dst, std::min(max, left));
        left -= n;
        return n;
      } catch (const std::runtime_error& e) {
        throw DatasetError(path, 0, 0, std::string(e.what()) + " (the file cannot be read to its end)");
      }
    };
  };
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  if (ec || bytes == 0) {
    // No size to cut into ranges (a pipe, a process substitution, /proc, an empty file; or no
    // such file): read as a stream, whole.
    std::ifstream in(path, std::ios::binary);
    if (!in) throw DatasetError(path, 0, 0, "cannot open file for reading");
    return parseDatasetCsv(in, path, options);
  }
  return parseLog(open, static_cast<std::int64_t>(bytes), path, options);
}

namespace {
// Cubic Hermite interpolation of y(t) at the sorted times tq, slopes from three points.
Eigen::VectorXd hermite(const Eigen::VectorXd& t, const Eigen::VectorXd& y, const Eigen::VectorXd& tq) {
  const Eigen::Index n = t.size();
  Eigen::VectorXd m(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (i == 0 || i == n - 1) {
      const Eigen::Index a = i == 0 ? 0 : n - 2;
      m[i] = (y[a + 1] - y[a]) / (t[a + 1] - t[a]);
      if (n >= 3) {  // second-order one-sided: exact for quadratics too
        const Eigen::Index b = i == 0 ? 0 : n - 3;
        const double h0 = t[b + 1] - t[b], h1 = t[b + 2] - t[b + 1];
        const double d0 = (y[b + 1] - y[b]) / h0, d1 = (y[b + 2] - y[b + 1]) / h1;
        m[i] = i == 0 ? d0 - h0 * (d1 - d0) / (h0 + h1) : d1 + h1 * (d1 - d0) / (h0 + h1);
      }
      continue;
    }
    const double h0 = t[i] - t[i - 1], h1 = t[i + 1] - t[i];
    const double d0 = (y[i] - y[i - 1]) / h0, d1 = (y[i + 1] - y[i]) / h1;
    m[i] = (h1 * d0 + h0 * d1) / (h0 + h1);  // the derivative of the parabola through the three points
  }
  Eigen::VectorXd out(tq.size());
  Eigen::Index k = 0;
  for (Eigen::Index q = 0; q < tq.size(); ++q) {
    while (k + 2 < n && t[k + 1] < tq[q]) ++k;
    const double h = t[k + 1] - t[k], s = (tq[q] - t[k]) / h;
    const double s2 = s * s, s3 = s2 * s;
    out[q] = (2 * s3 - 3 * s2 + 1) * y[k] + (s3 - 2 * s2 + s) * h * m[k] + (-2 * s3 + 3 * s2) * y[k + 1] + (s3 - s2) * h * m[k + 1];
  }
  return out;
}
}  // namespace

Dataset resampleUniform(const Dataset& d, double dt_s) {
  if (!(dt_s > 0) || d.size() < 2) throw std::invalid_argument("resampleUniform: needs dt > 0 and >= 2 rows");
  const double t0 = d.t_s[0], span = d.t_s[d.size() - 1] - t0;
  const auto n = static_cast<Eigen::Index>(std::floor(span / dt_s * (1.0 + 1e-12))) + 1;
  Eigen::VectorXd tq(n);
  for (Eigen::Index k = 0; k < n; ++k) tq[k] = t0 + static_cast<double>(k) * dt_s;
  const auto pair = [&](const Eigen::MatrixXd& m) {
    Eigen::MatrixXd out(n, m.cols());
    for (Eigen::Index j = 0; j < m.cols(); ++j) out.col(j) = hermite(d.t_s, m.col(j), tq);
    return out;
  };
  Dataset r;
  r.joints = d.joints;
  r.comments = d.comments;
  r.t_s = tq;
  r.q_rad = pair(d.q_rad);
  r.tau_Nm = pair(d.tau_Nm);
  if (d.qd_radps) r.qd_radps = pair(*d.qd_radps);
  if (d.qdd_radps2) r.qdd_radps2 = pair(*d.qdd_radps2);
  r.extra_names = d.extra_names;
  r.text_columns = d.text_columns;
  r.extra.resize(n, d.extra.cols());
  for (Eigen::Index c = 0; c < d.extra.cols(); ++c) r.extra.col(c) = hermite(d.t_s, d.extra.col(c), tq);
  r.sampling = d.sampling;
  r.sampling.resampled = true;
  return r;
}

void writeDatasetCsv(const Dataset& d, std::ostream& out) {
  const Eigen::Index n = d.size();
  const Eigen::Index dof = d.dof();
  const auto fits = [&](const Eigen::MatrixXd& m) { return m.rows() == n && m.cols() == dof; };
  if (!fits(d.q_rad) || !fits(d.tau_Nm) || (d.qd_radps && !fits(*d.qd_radps)) || (d.qdd_radps2 && !fits(*d.qdd_radps2)) ||
      (!d.extra_names.empty() && d.extra.rows() != n) || d.extra.cols() != static_cast<Eigen::Index>(d.extra_names.size())) {
    throw std::invalid_argument("dataset: column sizes disagree with t (" + core::toText(n) + " rows) and the joints (" +
                                core::toText(dof) + ")");
  }
  for (const std::string& c : d.comments) out << '#' << c << '\n';
  out << 't';
  for (const char* prefix : {"q_", "tau_"}) {
    for (const std::string& j : d.joints) out << ',' << prefix << j;
  }
  if (d.qd_radps) {
    for (const std::string& j : d.joints) out << ",qd_" << j;
  }
  if (d.qdd_radps2) {
    for (const std::string& j : d.joints) out << ",qdd_" << j;
  }
  for (const std::string& name : d.extra_names) out << ',' << name;
  out << '\n';
  char buf[32];
  auto put = [&](double v, bool first = false) {
    std::snprintf(buf, sizeof buf, "%.17g", v);
    if (!first) out << ',';
    out << buf;
  };
  for (Eigen::Index i = 0; i < n; ++i) {
    put(d.t_s[i], true);
    for (Eigen::Index j = 0; j < dof; ++j) put(d.q_rad(i, j));
    for (Eigen::Index j = 0; j < dof; ++j) put(d.tau_Nm(i, j));
    if (d.qd_radps) {
      for (Eigen::Index j = 0; j < dof; ++j) put((*d.qd_radps)(i, j));
    }
    if (d.qdd_radps2) {
      for (Eigen::Index j = 0; j < dof; ++j) put((*d.qdd_radps2)(i, j));
    }
    for (Eigen::Index k = 0; k < d.extra.cols(); ++k) put(d.extra(i, k));
    out << '\n';
  }
}

void writeDatasetCsv(const Dataset& d, const std::string& path) {
  core::writeFileAtomically(path, [&](std::ostream& out) { writeDatasetCsv(d, out); });
}

std::string angleUnitHint(const Dataset& d) {
  if (d.size() < 3) return "";
  const double dt = d.sampleInterval_s();
  // Speeds only at a plausible sampling rate: a time column in another unit is its own error.
  const bool rate_plausible = dt >= 1e-5 && dt <= 0.05;
  for (Eigen::Index j = 0; j < d.q_rad.cols(); ++j) {
    const auto q = d.q_rad.col(j);
    const double span = q.maxCoeff() - q.minCoeff();
    const auto m = static_cast<std::size_t>(d.size() - 2);
    const auto speedAt = [&](Eigen::Index i) { return std::abs(q[i + 1] - q[i - 1]) / (2.0 * dt); };
    const auto k = static_cast<std::size_t>(0.99 * static_cast<double>(m - 1));  // the 99th percentile's rank
    // The k-th smallest speed exceeds 100 rad/s exactly when fewer than k + 1 are <= 100: counted
    // in one pass; the percentile itself is sorted out only for the message.
    std::size_t slow = 0;
    if (rate_plausible) {
      for (Eigen::Index i = 1; i + 1 < d.size(); ++i) slow += speedAt(i) <= 100.0 ? 1 : 0;
    }
    const bool too_fast = rate_plausible && slow < k + 1;
    if (span <= 4.0 * M_PI && !too_fast) continue;
    double fast = 0.0;
    if (rate_plausible) {
      std::vector<double> speed(m);
      for (Eigen::Index i = 1; i + 1 < d.size(); ++i) speed[static_cast<std::size_t>(i - 1)] = speedAt(i);
      std::nth_element(speed.begin(), speed.begin() + static_cast<std::ptrdiff_t>(k), speed.end());
      fast = speed[k];
    }
    const std::string joint = static_cast<std::size_t>(j) < d.joints.size() ? d.joints[static_cast<std::size_t>(j)] : core::toText(j);
    return "q_" + joint + " spans " + core::formatNumber(span, 4) + " rad (" + core::formatNumber(span / (2.0 * M_PI), 3) +
           " turns) and moves at " + core::formatNumber(fast, 4) + " rad/s (99th percentile): implausible in radians for a robot joint "
           "(at most 2 turns, 100 rad/s); as degrees it would be " + core::formatNumber(span * M_PI / 180.0, 4) + " rad and " +
           core::formatNumber(fast * M_PI / 180.0, 4) + " rad/s. A log in degrees? Give --angle-unit deg (a profile: [units] angle = "
           "\"deg\"); --angle-unit rad says the radians are meant";
  }
  return "";
}

}  // namespace exoid::ident
