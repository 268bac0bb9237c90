#pragma once
// How the commands read logs: a lab's "log profile" (TOML: column names, units, torque signs,
// the model constants the log does not carry) and flags that override it, plain or gzipped CSV,
// and a one-line account of the sampling the reader found.
#include "exoid/ident/io/dataset.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace exoid::experiments {

struct LogInputFlags {
  std::string profile;                ///< --profile FILE.toml
  std::string columns;                ///< --columns t=time,q_hip=pos_meas1,...
  std::string time_unit, angle_unit;  ///< --time-unit s|ms|us, --angle-unit rad|deg
  std::vector<double> torque_sign;    ///< --torque-sign hip,knee (each +1 or -1)
  bool strict_sampling = false;       ///< --strict-sampling
  std::optional<double> max_gap_ms;   ///< --max-gap-ms
};
void addLogInputOptions(CLI::App& app, LogInputFlags& f);

/// The resolved reading options, and what the profile says about the model.
struct LogInput {
  ident::CsvReadOptions csv;
  std::optional<double> thigh_length_m, gravity_mps2;  ///< from the profile's [model]
  std::string profile;                                 ///< its path, if any
  /// The angle unit was said (--angle-unit or the profile's [units] angle): readLog trusts it;
  /// else it refuses angles implausible as radians, naming the likely unit (ident::angleUnitHint).
  bool angle_unit_given = false;
  /// Run by readLog on each record read (e.g. a chain command's: the record is of its chain).
  std::function<void(const std::string& path, const ident::Dataset&)> check_record;
};
/// Profile first, then the flags over it. `filter_cutoff_hz` > 0 sets the longest gap resampling
/// bridges to a tenth of the filter's period unless --max-gap-ms says otherwise. Throws
/// std::invalid_argument naming the profile's file:line:column or the flag.
/// `joints`: the model's (the APAL leg's hip, knee by default); the reader requires their columns
/// and a profile's [torque_sign] names them.
LogInput resolveLogInput(const LogInputFlags& f, double filter_cutoff_hz,
                         const std::vector<std::string>& joints = {"hip", "knee"});

/// Reads a profile TOML; throws std::invalid_argument naming file:line:column and the key.
LogInput readLogProfile(const std::string& path, const std::vector<std::string>& joints = {"hip", "knee"});

/// A dataset CSV, or a gzipped one (.gz). Throws ident::DatasetError naming the file.
ident::Dataset readLog(const std::string& path, const LogInput& in);

/// A hint for errors of a record sampled slower than 20 Hz ("" otherwise): its time column is
/// probably in ms or us.
std::string timeUnitHint(const ident::Dataset& d);

/// "2 ms median interval, 37 of 4999 off by > 0.1 % (longest 8.4 ms, line 1234): resampled to
/// 5012 rows", or "uniform, 1 ms" for a clean record.
std::string samplingSummary(const ident::Dataset& d, const ident::CsvReadOptions& o);
/// The same as identify's JSON gives it per record: rows read and used, the intervals, resampled.
nlohmann::json samplingJson(const ident::Dataset& d);

}  // namespace exoid::experiments
