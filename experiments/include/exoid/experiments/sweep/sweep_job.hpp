#pragma once
// One sweep job = one protocol run of one (cell, replicate), kept as a small JSON record: the
// raw numbers every score is computed from (estimates, truths, validation errors, each method's
// noise-limited std for its own processing, torque-space errors, optimality gaps). Doubles
// round-trip exactly.
#include "exoid/experiments/sweep/sweep_config.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace exoid::experiments {

struct JobId {
  int cell = 0;
  int replicate = 0;
};

/// Runs the job. Never throws for a failing run: a simulation or identification error becomes
/// status "error" with the message (so a resumed sweep does not retry it forever).
nlohmann::json runSweepJob(const SweepConfig& config, JobId id);

/// "job-CCCCC-RRRR.json" (relative to DIR/runs).
std::string jobFileName(JobId id);
/// Parses a job file name; nullopt for anything else (temporaries, foreign files).
std::optional<JobId> parseJobFileName(const std::string& name);

}  // namespace exoid::experiments
