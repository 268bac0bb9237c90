#pragma once
// The dataset CSV format: the one door for simulated and real logs.
//
//   # comment / metadata lines ("# key: value" by convention; anywhere, blank lines too)
//   t,q_hip,q_knee,tau_hip,tau_knee[,qd_hip,qd_knee,qdd_hip,qdd_knee][,any other column...]
//   0,-0.1745,0.7854,1.2,3.4
//
// That is the APAL leg's; a robot with other joints has q_<joint> and tau_<joint> (and qd_, qdd_)
// for each joint the model names (CsvReadOptions::joints), in the model's order.
//
// SI units: s, rad, rad/s, rad/s^2, N m, unless a LogFormat maps a lab's own column names, angle
// and time units and torque signs onto these. Columns may come in any order; names are exact.
// qd_* and qdd_* must each come in pairs (both joints). Other columns are kept when numeric and
// ignored when not. As lab tools write it: LF, CRLF or CR line ends, a UTF-8 byte-order mark,
// RFC 4180 double quotes, a trailing comma on every line. Jittered timestamps are resampled onto
// a uniform grid (SamplingMode).
#include <Eigen/Core>

#include <cstddef>
#include <iosfwd>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
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

/// What the reader found about the timestamps, and what it did.
struct SamplingReport {
  long rows_read = 0;          ///< data rows in the file
  double median_dt_s = 0.0;    ///< median interval
  double min_dt_s = 0.0, max_dt_s = 0.0;
  long max_dt_line = 0;        ///< file line of the row ending the longest interval
  long intervals_off = 0;      ///< intervals more than the tolerance away from the median
  bool resampled = false;      ///< the rows are a uniform grid interpolated from the file's
};

struct Dataset {
  std::vector<std::string> comments;  ///< metadata lines, without the leading '#'
  /// The joints, base to tip: column j of q_rad, tau_Nm, ... is joints[j] (the APAL leg: hip, knee).
  std::vector<std::string> joints = {"hip", "knee"};
  Eigen::VectorXd t_s;
  Eigen::MatrixXd q_rad;   ///< N x joints.size()
  Eigen::MatrixXd tau_Nm;  ///< measured joint (motor) torques
  std::optional<Eigen::MatrixXd> qd_radps;     ///< recorded velocities, if any
  std::optional<Eigen::MatrixXd> qdd_radps2;   ///< recorded accelerations, if any
  std::vector<std::string> extra_names;  ///< other numeric columns, in file order
  Eigen::MatrixXd extra;                 ///< N x extra_names.size()
  std::vector<std::string> text_columns;  ///< other columns with a non-numeric cell (ignored)
  SamplingReport sampling;

  Eigen::Index size() const { return t_s.size(); }
  Eigen::Index dof() const { return static_cast<Eigen::Index>(joints.size()); }
  /// Rows [from, from + n), every column. Throws std::invalid_argument outside the record.
  Dataset window(Eigen::Index from, Eigen::Index n) const;
  /// Throws std::invalid_argument unless the joints are exactly these (e.g. the APAL leg's
  /// hip, knee for the hand-written 2-link path), naming both lists.
  void requireJoints(const std::vector<std::string>& expected, const std::string& who) const;
  /// Mean sampling interval (s). Requires size() >= 2.
  double sampleInterval_s() const;
  /// Value of a "# key: value" metadata line, if present.
  std::optional<std::string> metadata(const std::string& key) const;
  /// Column of an extra column by name, or throws std::invalid_argument.
  Eigen::VectorXd extraColumn(const std::string& name) const;
};

/// How a lab's log maps onto the dataset's columns and units (a "log profile").
struct LogFormat {
  /// exoid's column name -> the log's (e.g. q_hip -> pos_meas1). Unmapped names are exoid's own.
  std::vector<std::pair<std::string, std::string>> columns;
  double time_scale_s = 1.0;     ///< seconds per unit of the time column (1e-3 for ms)
  double angle_scale_rad = 1.0;  ///< radians per unit of angles and their derivatives (pi/180 for deg)
  /// Multiplies each joint's torque (+1 or -1), in the joints' order; empty = all +1.
  std::vector<double> torque_sign;
  void validate() const;  ///< throws std::invalid_argument naming the field
};
/// "t=time,q_hip=pos_meas1,...": exoid name = log name pairs. Throws std::invalid_argument.
std::vector<std::pair<std::string, std::string>> parseColumnMap(const std::string& text);
/// A hint when the record's angles are implausible as radians: "" when they are plausible, else
/// one line naming the joint whose angle spans more than 4 pi rad (two turns: no leg joint does)
/// or whose speed (the 99th percentile of |central differences|, when sampled at 20 Hz to 100 kHz)
/// exceeds 100 rad/s, and the likely
/// cause, a log in degrees (--angle-unit deg). Needs size() >= 3.
std::string angleUnitHint(const Dataset& d);
/// "s", "ms", "us" -> seconds per unit. Throws std::invalid_argument listing them.
double parseTimeUnit(const std::string& unit);
/// "rad", "deg" -> radians per unit. Throws std::invalid_argument listing them.
double parseAngleUnit(const std::string& unit);

enum class SamplingMode {
  /// Intervals within dt_rel_tolerance of the median are kept as they are; otherwise the record
  /// is interpolated (cubic Hermite, three-point slopes: exact for quadratics) onto a uniform grid
  /// at the median interval, every column alike, provided no interval exceeds max_gap_s.
  kResample,
  /// Every interval within dt_rel_tolerance of the median, else an error naming the row.
  kStrict,
};

struct CsvReadOptions {
  /// The robot's joints, base to tip: the reader requires q_<joint> and tau_<joint> for each.
  /// Default: the APAL leg's.
  std::vector<std::string> joints = {"hip", "knee"};
  /// Fewer data rows than this is an error: differentiation and filtering need a record.
  long min_rows = 20;
  /// An interval within dt_rel_tolerance * median of the median counts as uniform.
  double dt_rel_tolerance = 1e-3;
  SamplingMode sampling = SamplingMode::kResample;
  /// Resampling refuses a record with an interval longer than this (s): the interpolation would
  /// invent the motion in between. <= 0: 10 median intervals. `exoid identify` passes a tenth of
  /// its low-pass filter's period (10 ms at 10 Hz).
  double max_gap_s = 0.0;
  LogFormat format;
  /// Threads parsing the data rows (0 = the machine's cores): a long log's rows are cut into
  /// ranges of about range_bytes, each parsed on its own; the result, and the first error in the
  /// file when there is one, are the same whatever the number.
  int threads = 0;
  std::size_t range_bytes = std::size_t(4) << 20;
};

/// Reads a dataset; throws DatasetError (file, line, column) on anything malformed.
Dataset readDatasetCsv(const std::string& path, const CsvReadOptions& options = {});
/// Same from a stream; `source` names it in messages.
Dataset parseDatasetCsv(std::istream& in, const std::string& source, const CsvReadOptions& options = {});
/// Same from the file's text (e.g. decompressed by the caller).
Dataset parseDatasetText(std::string_view text, const std::string& source, const CsvReadOptions& options = {});

/// The record interpolated onto t0 + k dt (k = 0 .. while <= the last time), every signal and
/// numeric extra column by cubic Hermite interpolation with three-point slopes (exact for
/// polynomials of degree <= 2). Throws std::invalid_argument for dt <= 0 or < 2 rows.
Dataset resampleUniform(const Dataset& d, double dt_s);

/// Writes with full double precision (%.17g): reading it back gives identical values.
void writeDatasetCsv(const Dataset& d, std::ostream& out);
/// Writes atomically (temporary file + rename): never a half-written file.
void writeDatasetCsv(const Dataset& d, const std::string& path);

}  // namespace exoid::ident
