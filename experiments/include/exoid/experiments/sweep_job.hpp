#pragma once
// One sweep job = one protocol run of one (cell, replicate), kept as a small JSON record: the
// raw numbers every score is computed from (estimates, truths, validation errors, the
// Cramer-Rao bound of the condition's exact regressors). Doubles round-trip exactly.
#include "exoid/experiments/sweep_config.hpp"

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

/// Cramer-Rao lower bound of each parameter's std (order of X) for torque noise `sigma_Nm`:
/// knee block from the knee stage of record 1, hip block from the hip stage of record 3, both
/// on the exact states with the ideal torques. 0 noise gives 0.
Eigen::VectorXd cramerRaoStd(const ProtocolResult& r, double sigma_Nm);

/// "job-CCCCC-RRRR.json" (relative to DIR/runs).
std::string jobFileName(JobId id);
/// Parses a job file name; nullopt for anything else (temporaries, foreign files).
std::optional<JobId> parseJobFileName(const std::string& name);

}  // namespace exoid::experiments
