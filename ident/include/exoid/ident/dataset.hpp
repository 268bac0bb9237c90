#pragma once
// The dataset CSV format: the one door for simulated and real logs.
//
//   # comment / metadata lines (optional, only before the header; "# key: value" by convention)
//   t,q_hip,q_knee,tau_hip,tau_knee[,qd_hip,qd_knee,qdd_hip,qdd_knee][,any other column...]
//   0,-0.1745,0.7854,1.2,3.4
//
// SI units: s, rad, rad/s, rad/s^2, N m. Columns may come in any order; names are exact.
// qd_* and qdd_* must come in pairs (both joints). Other columns are kept, not used.
#include <Eigen/Core>

#include <iosfwd>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace exoid::ident {

/// A read error that names where: "file:line:column: what was expected".
class DatasetError : public std::runtime_error {
 public:
  DatasetError(std::string source, long line, long column, const std::string& what);
  const std::string& source() const { return source_; }
  long line() const { return line_; }      ///< 1-based; 0 if not about one line
  long column() const { return column_; }  ///< 1-based; 0 if not about one column
 private:
  std::string source_;
  long line_;
  long column_;
};

struct Dataset {
  std::vector<std::string> comments;  ///< metadata lines, without the leading '#'
  Eigen::VectorXd t_s;
  Eigen::MatrixX2d q_rad;   ///< col 0 hip, col 1 knee
  Eigen::MatrixX2d tau_Nm;  ///< measured joint (motor) torques
  std::optional<Eigen::MatrixX2d> qd_radps;     ///< recorded velocities, if any
  std::optional<Eigen::MatrixX2d> qdd_radps2;   ///< recorded accelerations, if any
  std::vector<std::string> extra_names;  ///< other columns, in file order
  Eigen::MatrixXd extra;                 ///< N x extra_names.size()

  Eigen::Index size() const { return t_s.size(); }
  /// Mean sampling interval (s). Requires size() >= 2.
  double sampleInterval_s() const;
  /// Value of a "# key: value" metadata line, if present.
  std::optional<std::string> metadata(const std::string& key) const;
  /// Column of an extra column by name, or throws std::invalid_argument.
  Eigen::VectorXd extraColumn(const std::string& name) const;
};

struct CsvReadOptions {
  /// Fewer data rows than this is an error: differentiation and filtering need a record.
  long min_rows = 20;
  /// Every interval must be within dt_rel_tolerance * median interval of the median (uniform sampling).
  double dt_rel_tolerance = 1e-3;
};

/// Reads a dataset; throws DatasetError (file, line, column) on anything malformed.
Dataset readDatasetCsv(const std::string& path, const CsvReadOptions& options = {});
/// Same from a stream; `source` names it in messages.
Dataset parseDatasetCsv(std::istream& in, const std::string& source, const CsvReadOptions& options = {});

/// Writes with full double precision (%.17g): reading it back gives identical values.
void writeDatasetCsv(const Dataset& d, std::ostream& out);
/// Writes atomically (temporary file + rename): never a half-written file.
void writeDatasetCsv(const Dataset& d, const std::string& path);

}  // namespace exoid::ident
