#pragma once
// The sweep's deterministic outputs from its job records: runs.csv (one row per job x method),
// summary.csv / summary.json / summary.md (per condition and method: mean, std, 95 % Student-t
// CI; paired Wilcoxon comparison against LS; Cramer-Rao bound and RMS error relative to it).
// Nothing here depends on wall time, thread count, shard split or resume history, except the
// last column of runs.csv (wall_time_s).
#include "exoid/experiments/sweep/sweep_config.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace exoid::experiments {

/// What the tables need to know of a sweep: its cells, methods and resolved configuration
/// (rebuilt from a folder's config.json by `exoid merge`).
struct SweepLayout {
  std::vector<SweepCondition> cells;
  std::vector<Variant> methods;
  int seeds = 0;
  nlohmann::json resolved;  ///< SweepConfig::toJson()
  const std::vector<SweepCondition>& conditions() const { return cells; }
};
SweepLayout layoutOf(const SweepConfig& c);
/// From a resolved configuration (config.json); throws std::runtime_error when malformed.
SweepLayout layoutFromJson(const nlohmann::json& resolved);

/// `jobs` sorted by (cell, replicate). Writes runs.csv, summary.csv, summary.json, summary.md
/// into `dir` (atomically, file by file).
void writeSweepTables(const SweepLayout& config, const std::vector<nlohmann::json>& jobs, const std::string& dir);

/// The summary as JSON (what summary.json holds).
nlohmann::json sweepSummaryJson(const SweepLayout& config, const std::vector<nlohmann::json>& jobs);

}  // namespace exoid::experiments
