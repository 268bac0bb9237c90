#include "exoid/ident/io/dataset.hpp"

#include "exoid/core/atomic_file.hpp"
#include "exoid/core/format.hpp"

#include "csv_lines.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <iterator>
#include <string_view>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
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

std::string joinNames(const std::vector<std::string>& names, const char* separator) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : separator) + n;
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
    throw std::invalid_argument(who + " needs a record of the joints " + joinNames(expected, ", ") + "; this one has " +
                                joinNames(joints, ", ") + " (pass the robot's model, --model)");
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
  cell = csv::trimBlanks(cell);
  if (!cell.empty() && cell[0] == '+') cell.remove_prefix(1);
  if (cell.empty()) return false;
  const auto r = std::from_chars(cell.data(), cell.data() + cell.size(), v);
  return r.ec == std::errc() && r.ptr == cell.data() + cell.size();
}

std::string listNames(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
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

// The reader proper, one step per member: the header (names, column map, required columns,
// allocation), each data row, then text columns, units and the time axis.
class LogParser {
 public:
  LogParser(const std::string& source, const CsvReadOptions& options, Eigen::Index rows)
      : source_(source), options_(options), rows_(rows) {}

  void line(const csv::Line& line) {
    if (line.comment) {
      d_.comments.emplace_back(line.text);
    } else if (header_line_ == 0) {
      header(line);
    } else if (row_ < rows_) {
      dataRow(line);
    }
  }

  Dataset finish() {
    if (header_line_ == 0) {
      throw DatasetError(source_, 0, 0, "empty file: expected a header line '" + joinNames(requiredColumns(options_.joints), ",") +
                                            "' followed by data rows");
    }
    if (row_ < options_.min_rows) {
      throw DatasetError(source_, 0, 0,
                         "expected at least " + core::toText(options_.min_rows) + " data rows, got " + core::toText(row_));
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
    allocate();
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
                           "column '" + theirs + "' (mapped to " + ours + ") is not in the header; it has: " + listNames(file_names));
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
                           "missing required column '" + r + "' (required: " + joinNames(required, ",") +
                               "; a log with its own names needs a column map, e.g. --columns t=time,q_" + options_.joints.front() +
                               "=pos_meas1,...); the header has: " + listNames(names_));
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
                               joinNames(options_.joints, ", ") + ") does not: it is another robot's record; give its model (--model)");
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
                                 joinNames(options_.joints, ", ") + ") or for none");
        }
      }
    }
  }

  // Every column at its final size (the first pass counted the rows): parsed straight into place.
  void allocate() {
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
      known_.push_back(isKnown(names_[c], options_.joints));
      bound_.push_back(physicalBound(names_[c]));  // once per column, not per cell (the hot loop)
    }
    row_lines_.reserve(static_cast<std::size_t>(n));
  }

  void dataRow(const csv::Line& line) {
    std::size_t cells = line.cells.size();
    if (trailing_comma_ && cells == ncol_ + 1 && csv::trimBlanks(line.cells.back()).empty()) --cells;
    if (cells != ncol_) {
      throw DatasetError(source_, line.number, 0,
                         "expected " + core::toText(ncol_) + " cells as in the header, got " + core::toText(cells));
    }
    for (std::size_t c = 0; c < ncol_; ++c) {
      if (!target_[c]) continue;
      double v = 0.0;
      const bool ok = parseNumber(line.cells[c], v);
      const long col = static_cast<long>(c) + 1;
      if (!known_[c]) {
        if (!ok || !std::isfinite(v)) target_[c] = nullptr;  // an extra column that is not a number: dropped
        if (!target_[c]) continue;
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
      target_[c][row_] = v;
    }
    row_lines_.push_back(line.number);
    ++row_;
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
    const std::vector<double> dts = intervals();
    SamplingReport& rep = d_.sampling;
    rep.rows_read = static_cast<long>(row_);
    rep.median_dt_s = median(dts);
    rep.min_dt_s = *std::min_element(dts.begin(), dts.end());
    const auto longest = std::max_element(dts.begin(), dts.end());
    rep.max_dt_s = *longest;
    rep.max_dt_line = row_lines_[static_cast<std::size_t>(longest - dts.begin()) + 1];
    long first_off = -1;
    for (std::size_t i = 0; i < dts.size(); ++i) {
      if (std::abs(dts[i] - rep.median_dt_s) > options_.dt_rel_tolerance * rep.median_dt_s) {
        ++rep.intervals_off;
        if (first_off < 0) first_off = static_cast<long>(i) + 1;
      }
    }
    if (rep.intervals_off == 0) return std::move(d_);
    if (options_.sampling == SamplingMode::kStrict) {
      char buf[240];
      std::snprintf(buf, sizeof buf,
                    "sampling is not uniform: interval %.9g s differs from the median %.9g s by more than %.3g %% (%ld "
                    "such intervals; without strict sampling the record would be resampled)",
                    dts[static_cast<std::size_t>(first_off - 1)], rep.median_dt_s, 100.0 * options_.dt_rel_tolerance,
                    rep.intervals_off);
      throw DatasetError(source_, row_lines_[static_cast<std::size_t>(first_off)], timeColumn(), buf);
    }
    checkGaps(dts, static_cast<std::size_t>(longest - dts.begin()));
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

  std::vector<double> intervals() const {
    std::vector<double> dts(static_cast<std::size_t>(row_ - 1));
    for (Eigen::Index i = 1; i < row_; ++i) {
      const double dt = d_.t_s[i] - d_.t_s[i - 1];
      if (!(dt > 0.0)) {
        throw DatasetError(source_, row_lines_[static_cast<std::size_t>(i)], timeColumn(),
                           "time must be strictly increasing: t = " + core::toText(d_.t_s[i]) +
                               " s after t = " + core::toText(d_.t_s[i - 1]) + " s");
      }
      dts[static_cast<std::size_t>(i - 1)] = dt;
    }
    return dts;
  }

  // Resampling bridges short gaps only: a longer one is a break in the log.
  void checkGaps(const std::vector<double>& dts, std::size_t k) const {
    const SamplingReport& rep = d_.sampling;
    const double max_gap = options_.max_gap_s > 0 ? options_.max_gap_s : 10.0 * rep.median_dt_s;
    if (dts[k] <= max_gap) return;
    char buf[300];
    std::snprintf(buf, sizeof buf,
                  "a gap of %.6g s between lines %ld and %ld (t = %.6g .. %.6g s) is longer than the %.6g s resampling "
                  "bridges (the median interval is %.6g s): split the log there, or raise the limit",
                  dts[k], row_lines_[k], row_lines_[k + 1], d_.t_s[static_cast<Eigen::Index>(k)],
                  d_.t_s[static_cast<Eigen::Index>(k + 1)], max_gap, rep.median_dt_s);
    throw DatasetError(source_, row_lines_[k + 1], timeColumn(), buf);
  }

  long timeColumn() const { return index_.at("t") + 1; }

  const std::string& source_;
  const CsvReadOptions& options_;
  const Eigen::Index rows_;  // data lines the first pass counted
  Dataset d_;
  std::vector<std::string> names_;
  long header_line_ = 0;
  bool trailing_comma_ = false;
  std::map<std::string, long> index_;  // exoid name -> 0-based column
  std::vector<double*> target_;        // per column: where its values go (nullptr: a text column)
  std::vector<bool> known_;
  std::vector<double> bound_;           // per column: the largest physical magnitude
  std::vector<long> row_lines_;
  std::size_t ncol_ = 0;
  Eigen::Index row_ = 0;
};

// `open` returns a fresh chunk reader (read(buffer) -> bool) for each of two passes: the first
// counts the data rows, so every column is allocated once at its final size.
template <typename Open>
Dataset parseLog(Open&& open, const std::string& source, const CsvReadOptions& options) {
  try {
    options.format.validate();
    if (options.joints.empty()) throw std::invalid_argument("dataset: the model names no joints");
    for (std::size_t j = 0; j < options.joints.size(); ++j) {
      if (options.joints[j].empty() || std::count(options.joints.begin(), options.joints.end(), options.joints[j]) > 1) {
        throw std::invalid_argument("dataset: joint names must be distinct and non-empty, got " + joinNames(options.joints, ", "));
      }
    }
    if (!options.format.torque_sign.empty() && options.format.torque_sign.size() != options.joints.size()) {
      throw std::invalid_argument("log format: " + core::toText(options.format.torque_sign.size()) + " torque signs for " +
                                  core::toText(options.joints.size()) + " joints (" + joinNames(options.joints, ", ") + ")");
    }
  } catch (const std::invalid_argument& e) {
    throw DatasetError(source, 0, 0, e.what());
  }
  csv::LineSplitter splitter;
  Eigen::Index rows = -1;  // data lines after the header
  try {
    splitter.run(open(), [&](const csv::Line& line) { rows += line.comment ? 0 : 1; }, false);
  } catch (const csv::SyntaxError& e) {
    throw DatasetError(source, e.line, e.column, e.what);
  }
  LogParser parser(source, options, rows);
  try {
    splitter.run(open(), [&](const csv::Line& line) { parser.line(line); });
  } catch (const csv::SyntaxError& e) {
    throw DatasetError(source, e.line, e.column, e.what);
  }
  return parser.finish();
}

}  // namespace

Dataset parseDatasetText(std::string_view text, const std::string& source, const CsvReadOptions& options) {
  return parseLog(
      [text] {
        return [text, done = false](std::string& buf) mutable {
          if (done) return false;
          buf.append(text);
          done = true;
          return !text.empty();
        };
      },
      source, options);
}

Dataset parseDatasetCsv(std::istream& in, const std::string& source, const CsvReadOptions& options) {
  std::string text;
  try {
    while (csv::readChunk(in, text)) {
    }
  } catch (const std::runtime_error& e) {
    throw DatasetError(source, 0, 0, std::string(e.what()) + " after " + core::toText(text.size()) + " bytes");
  }
  return parseDatasetText(text, source, options);
}

Dataset readDatasetCsv(const std::string& path, const CsvReadOptions& options) {
  std::shared_ptr<std::ifstream> in;
  const auto open = [&] {
    in = std::make_shared<std::ifstream>(path, std::ios::binary);
    if (!*in) throw DatasetError(path, 0, 0, "cannot open file for reading");
    return [in, path](std::string& buf) {
      try {
        return csv::readChunk(*in, buf);
      } catch (const std::runtime_error& e) {
        throw DatasetError(path, 0, 0, std::string(e.what()) + " (the file cannot be read to its end)");
      }
    };
  };
  return parseLog(open, path, options);
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
  for (Eigen::Index j = 0; j < d.q_rad.cols(); ++j) {
    const auto q = d.q_rad.col(j);
    const double span = q.maxCoeff() - q.minCoeff();
    std::vector<double> speed(static_cast<std::size_t>(d.size() - 2));
    for (Eigen::Index i = 1; i + 1 < d.size(); ++i) speed[static_cast<std::size_t>(i - 1)] = std::abs(q[i + 1] - q[i - 1]) / (2.0 * dt);
    const auto k = static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(speed.size() - 1));
    std::nth_element(speed.begin(), speed.begin() + k, speed.end());
    // Speeds only at a plausible sampling rate: a time column in another unit is its own error.
    const bool rate_plausible = dt >= 1e-5 && dt <= 0.05;
    const double fast = rate_plausible ? speed[static_cast<std::size_t>(k)] : 0.0;
    if (span > 4.0 * M_PI || fast > 100.0) {
      const std::string joint = static_cast<std::size_t>(j) < d.joints.size() ? d.joints[static_cast<std::size_t>(j)] : core::toText(j);
      return "q_" + joint + " spans " + core::formatNumber(span, 4) + " rad (" + core::formatNumber(span / (2.0 * M_PI), 3) +
             " turns) and moves at " + core::formatNumber(fast, 4) + " rad/s (99th percentile): implausible in radians for a robot joint "
             "(at most 2 turns, 100 rad/s); as degrees it would be " + core::formatNumber(span * M_PI / 180.0, 4) + " rad and " +
             core::formatNumber(fast * M_PI / 180.0, 4) + " rad/s. A log in degrees? Give --angle-unit deg (a profile: [units] angle = "
             "\"deg\"); --angle-unit rad says the radians are meant";
    }
  }
  return "";
}

}  // namespace exoid::ident
