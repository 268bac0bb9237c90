#pragma once
// `exoid sweep --model M` on any serial chain: the same grid, seeds, resume, shards, merge and
// tables (sweep_summary.hpp) as the APAL leg's sweep, with the chain's own run. A run simulates a
// fit record (the sweep's design, or the simulator's default motion of its seed) and a validation
// record (the default motion of another seed), processes them as `exoid identify --model` does
// (the band from the data), and fits every method in the model's base parameters, scored against
// the simulation's truth: each base parameter's error, the validation torque error per joint, and
// LS's own standard errors against its actual errors.
#include "exoid/experiments/sweep/sweep_job.hpp"
#include "exoid/experiments/sweep/sweep_summary.hpp"

#include <nlohmann/json.hpp>

#include <ostream>
#include <string>
#include <vector>

namespace exoid::experiments {

/// A chain config's run of one condition and seed: its "truth", "base_parameters" and "methods"
/// (runSweepJob wraps it in the job record). Throws when the run cannot be simulated.
nlohmann::json runChainSweepRun(const SweepConfig& config, const SweepCondition& condition, std::uint64_t seed);

/// The sweep's "optimised" record when [simulation] excitation gives none: the one in the folder's
/// config.json when the sweep was started there before (resume, rerun, another shard), else
/// `exoid excite --model` with its defaults and the seed deriveSeed(master_seed, 0), written to
/// dir/design.json.
SweepConfig withChainDesign(SweepConfig config, const std::string& dir, std::ostream& log);

}  // namespace exoid::experiments
