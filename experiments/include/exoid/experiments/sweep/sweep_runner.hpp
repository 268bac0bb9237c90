#pragma once
// Running a sweep into a folder, crash-safe and resumable, and merging shard folders.
//
// Folder layout: config.json (resolved configuration; a resume must match it), shard.json,
// runs/job-CCCCC-RRRR.json (one per finished job, written via temporary + rename), and the
// outputs runs.csv, summary.{csv,json,md}, timing.json, *.png.
#include "exoid/core/format.hpp"
#include "exoid/experiments/sweep/sweep_config.hpp"
#include "exoid/experiments/sweep/sweep_job.hpp"

#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace exoid::experiments {

/// Shard K of N runs the cells with cell % N == K.
struct ShardSpec {
  int index = 0;
  int count = 1;
  std::string text() const { return core::toText(index) + "/" + core::toText(count); }
};
/// "K/N" with 0 <= K < N; throws std::invalid_argument otherwise.
ShardSpec parseShard(const std::string& s);
/// From SLURM_ARRAY_TASK_ID (minus SLURM_ARRAY_TASK_MIN when set) and SLURM_ARRAY_TASK_COUNT.
std::optional<ShardSpec> shardFromEnvironment();

/// Jobs of a shard in (cell, replicate) order.
std::vector<JobId> shardJobs(const SweepConfig& c, ShardSpec shard);

struct SweepRunOptions {
  std::string out = "results/sweep";
  int threads = 0;  ///< 0 = hardware concurrency
  ShardSpec shard;
  bool plots = true;
  int progress_tty = -1;  ///< -1: isatty(stderr)
  /// A finished folder whose outputs differ from complete.json's sizes and digests (edited by
  /// hand): refuse, naming them, instead of rewriting them (missing ones alone are rewritten).
  bool keep_edits = false;
};

struct SweepRunReport {
  long jobs = 0, skipped = 0, ran = 0;
  double wall_time_s = 0.0;
};

/// Validates, prepares or resumes the folder, runs the missing jobs on `threads` workers, and
/// writes the outputs. Throws (before any work) on a config or folder mismatch.
SweepRunReport runSweep(const SweepConfig& config, const SweepRunOptions& o, std::ostream& log);

/// Combines shard folders (same config.json, together every job of the grid) into `out`:
/// the same runs/, runs.csv and summary.* as a single-process run.
void mergeSweeps(const std::vector<std::string>& shard_dirs, const std::string& out, bool plots, std::ostream& log,
                 bool keep_edits = false);

}  // namespace exoid::experiments
