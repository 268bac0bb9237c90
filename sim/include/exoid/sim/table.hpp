#pragma once
// A table with named columns and metadata, and the dataset CSV writer (the format ident reads):
//   # key: value        (metadata, optional)
//   t,q_hip,q_knee,...  (header)
//   numbers as "%.17g", comma-separated; written atomically (temporary file + rename).
#include <Eigen/Core>

#include <string>
#include <utility>
#include <vector>

namespace exoid::sim {

struct Table {
  std::vector<std::string> names;                               ///< column names
  Eigen::MatrixXd values;                                       ///< rows x names.size()
  std::vector<std::pair<std::string, std::string>> metadata;    ///< "# key: value" lines

  Eigen::Index rows() const { return values.rows(); }
  /// Column index by name; throws std::invalid_argument listing the names if absent.
  Eigen::Index column(const std::string& name) const;
  /// Copy of a column by name.
  Eigen::VectorXd col(const std::string& name) const { return values.col(column(name)); }
  bool has(const std::string& name) const;
};

/// Writes the table as CSV to `path` atomically; throws std::runtime_error naming the path.
void writeTableCsv(const Table& table, const std::string& path);
/// The CSV text (same bytes as the file).
std::string tableCsv(const Table& table);

}  // namespace exoid::sim
