#include "exoid/ident/dataset.hpp"

#include "exoid/ident/atomic_file.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

namespace exoid::ident {

namespace {

std::string where(const std::string& source, long line, long column) {
  std::string s = source;
  if (line > 0) s += ":" + std::to_string(line);
  if (column > 0) s += ":" + std::to_string(column);
  return s;
}

constexpr std::array<const char*, 5> kRequired = {"t", "q_hip", "q_knee", "tau_hip", "tau_knee"};
constexpr std::array<const char*, 4> kDerivatives = {"qd_hip", "qd_knee", "qdd_hip", "qdd_knee"};

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> splitCommas(const std::string& line) {
  std::vector<std::string> cells;
  std::string::size_type start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    cells.push_back(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return cells;
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

Dataset parseDatasetCsv(std::istream& in, const std::string& source, const CsvReadOptions& options) {
  Dataset d;
  std::string line;
  long line_no = 0;
  // Comments, then the header.
  std::vector<std::string> names;
  long header_line = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim(line);
    if (t.empty()) continue;
    if (t[0] == '#') {
      d.comments.push_back(t.substr(1));
      continue;
    }
    names = splitCommas(t);
    header_line = line_no;
    break;
  }
  if (header_line == 0) {
    throw DatasetError(source, 0, 0,
                       "empty file: expected a header line 't,q_hip,q_knee,tau_hip,tau_knee' "
                       "followed by data rows");
  }
  std::map<std::string, long> index;  // name -> 0-based column
  for (std::size_t c = 0; c < names.size(); ++c) {
    names[c] = trim(names[c]);
    const long col = static_cast<long>(c) + 1;
    if (names[c].empty()) throw DatasetError(source, header_line, col, "empty column name in header");
    if (!index.emplace(names[c], static_cast<long>(c)).second) {
      throw DatasetError(source, header_line, col, "duplicate column '" + names[c] + "'");
    }
  }
  for (const char* r : kRequired) {
    if (!index.count(r)) {
      throw DatasetError(source, header_line, 0,
                         std::string("missing required column '") + r +
                             "' (required: t,q_hip,q_knee,tau_hip,tau_knee)");
    }
  }
  const bool has_qd = index.count("qd_hip") || index.count("qd_knee");
  const bool has_qdd = index.count("qdd_hip") || index.count("qdd_knee");
  for (const char* r : kDerivatives) {
    const std::string n = r;
    const bool needed = n.rfind("qdd", 0) == 0 ? has_qdd : has_qd;
    if (needed && !index.count(n)) {
      throw DatasetError(source, header_line, 0,
                         "missing column '" + n + "': derivative columns come in hip/knee pairs");
    }
  }

  // Data rows, column-major buffers.
  const std::size_t ncol = names.size();
  std::vector<std::vector<double>> cols(ncol);
  std::vector<long> row_lines;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim(line);
    if (t.empty()) continue;
    if (t[0] == '#') {
      throw DatasetError(source, line_no, 1, "comment lines are only allowed before the header");
    }
    const auto cells = splitCommas(t);
    if (cells.size() != ncol) {
      throw DatasetError(source, line_no, 0,
                         "expected " + std::to_string(ncol) + " cells as in the header, got " +
                             std::to_string(cells.size()));
    }
    for (std::size_t c = 0; c < ncol; ++c) {
      const std::string cell = trim(cells[c]);
      const long col = static_cast<long>(c) + 1;
      char* end = nullptr;
      errno = 0;
      const double v = cell.empty() ? 0.0 : std::strtod(cell.c_str(), &end);
      if (cell.empty() || end != cell.c_str() + cell.size()) {
        throw DatasetError(source, line_no, col,
                           "column '" + names[c] + "': expected a number, got '" + cell + "'");
      }
      if (!std::isfinite(v)) {
        throw DatasetError(source, line_no, col,
                           "column '" + names[c] + "': expected a finite number, got '" + cell + "'");
      }
      cols[c].push_back(v);
    }
    row_lines.push_back(line_no);
  }
  const auto n = static_cast<Eigen::Index>(row_lines.size());
  if (n < options.min_rows) {
    throw DatasetError(source, 0, 0,
                       "expected at least " + std::to_string(options.min_rows) + " data rows, got " +
                           std::to_string(n));
  }

  auto column = [&](const std::string& name) {
    return Eigen::Map<const Eigen::VectorXd>(cols[static_cast<std::size_t>(index.at(name))].data(), n);
  };
  auto pair = [&](const char* hip, const char* knee) {
    Eigen::MatrixX2d m(n, 2);
    m.col(0) = column(hip);
    m.col(1) = column(knee);
    return m;
  };
  d.t_s = column("t");
  d.q_rad = pair("q_hip", "q_knee");
  d.tau_Nm = pair("tau_hip", "tau_knee");
  if (has_qd) d.qd_radps = pair("qd_hip", "qd_knee");
  if (has_qdd) d.qdd_radps2 = pair("qdd_hip", "qdd_knee");

  // Time strictly increasing and uniformly sampled.
  const long t_col = index.at("t") + 1;
  std::vector<double> dts(static_cast<std::size_t>(n - 1));
  for (Eigen::Index i = 1; i < n; ++i) {
    const double dt = d.t_s[i] - d.t_s[i - 1];
    if (!(dt > 0.0)) {
      throw DatasetError(source, row_lines[static_cast<std::size_t>(i)], t_col,
                         "time must be strictly increasing: t = " + std::to_string(d.t_s[i]) +
                             " s after t = " + std::to_string(d.t_s[i - 1]) + " s");
    }
    dts[static_cast<std::size_t>(i - 1)] = dt;
  }
  const double dt_med = median(dts);
  for (Eigen::Index i = 1; i < n; ++i) {
    const double dt = dts[static_cast<std::size_t>(i - 1)];
    if (std::abs(dt - dt_med) > options.dt_rel_tolerance * dt_med) {
      char buf[200];
      std::snprintf(buf, sizeof buf,
                    "sampling is not uniform: interval %.9g s differs from the median %.9g s by "
                    "more than %.3g %%",
                    dt, dt_med, 100.0 * options.dt_rel_tolerance);
      throw DatasetError(source, row_lines[static_cast<std::size_t>(i)], t_col, buf);
    }
  }

  for (std::size_t c = 0; c < ncol; ++c) {
    bool known = false;
    for (const char* r : kRequired) known = known || names[c] == r;
    for (const char* r : kDerivatives) known = known || names[c] == r;
    if (!known) d.extra_names.push_back(names[c]);
  }
  d.extra.resize(n, static_cast<Eigen::Index>(d.extra_names.size()));
  for (std::size_t k = 0; k < d.extra_names.size(); ++k) {
    d.extra.col(static_cast<Eigen::Index>(k)) = column(d.extra_names[k]);
  }
  return d;
}

Dataset readDatasetCsv(const std::string& path, const CsvReadOptions& options) {
  std::ifstream in(path);
  if (!in) throw DatasetError(path, 0, 0, "cannot open file for reading");
  return parseDatasetCsv(in, path, options);
}

void writeDatasetCsv(const Dataset& d, std::ostream& out) {
  const Eigen::Index n = d.size();
  if (d.q_rad.rows() != n || d.tau_Nm.rows() != n || (!d.extra_names.empty() && d.extra.rows() != n) ||
      d.extra.cols() != static_cast<Eigen::Index>(d.extra_names.size())) {
    throw std::invalid_argument("dataset: column sizes disagree with t (" + std::to_string(n) + " rows)");
  }
  for (const std::string& c : d.comments) out << '#' << c << '\n';
  out << "t,q_hip,q_knee,tau_hip,tau_knee";
  if (d.qd_radps) out << ",qd_hip,qd_knee";
  if (d.qdd_radps2) out << ",qdd_hip,qdd_knee";
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
    put(d.q_rad(i, 0));
    put(d.q_rad(i, 1));
    put(d.tau_Nm(i, 0));
    put(d.tau_Nm(i, 1));
    if (d.qd_radps) {
      put((*d.qd_radps)(i, 0));
      put((*d.qd_radps)(i, 1));
    }
    if (d.qdd_radps2) {
      put((*d.qdd_radps2)(i, 0));
      put((*d.qdd_radps2)(i, 1));
    }
    for (Eigen::Index k = 0; k < d.extra.cols(); ++k) put(d.extra(i, k));
    out << '\n';
  }
}

void writeDatasetCsv(const Dataset& d, const std::string& path) {
  writeFileAtomically(path, [&](std::ostream& out) { writeDatasetCsv(d, out); });
}

}  // namespace exoid::ident
