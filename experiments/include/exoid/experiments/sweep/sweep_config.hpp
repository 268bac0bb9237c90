#pragma once
// The grid of `exoid sweep`: read from TOML (experiments/configs/default_sweep.toml), overridden
// by flags, validated before any work starts. Cells are the full factorial of the grid lists;
// a job is (cell, replicate) and its seed derives from (master seed, cell, replicate) only, where
// the identification trajectories (paper | optimised) do not count as part of the cell: a paper
// cell and its optimised twin share their seeds (common random numbers), so they pair.
#include "exoid/experiments/protocol/protocol.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace exoid::experiments {

/// A bad sweep configuration; the message names the key (and file:line when known).
class SweepConfigError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// One grid cell: the factor levels that vary between cells.
struct SweepCondition {
  double torque_noise_Nm = 0.0;
  double angle_noise_deg = 0.0;
  double quantisation_deg = 0.0;
  double vibration_level = 0.0;
  double cylinder_mass_scale = 0.0;
  /// The identification records: "paper" (trajectories 1 and 3) or "optimised" (the designs of
  /// [simulation] excitation_knee / excitation_both). Validation stays on trajectories 2 and 4.
  std::string trajectories = "paper";
};

struct SweepConfig {
  // [grid]: every combination is a cell (order: trajectories, cylinder, vibration, angle noise,
  // quantisation, torque noise; torque noise varies fastest).
  std::vector<std::string> trajectories{"paper"};               ///< "paper", "optimised"
  std::vector<double> torque_noise_Nm{0.0, 0.1, 0.5, 1.0, 2.0};  ///< >= 0
  std::vector<double> angle_noise_deg{0.005};                   ///< >= 0
  std::vector<double> quantisation_deg{360.0 / 131072.0};       ///< >= 0 (0 = none)
  std::vector<double> vibration_level{0.0, 1.0, 2.0};           ///< [0, 20], 0 = welded mount
  std::vector<double> cylinder_mass_scale{0.0, 1.0};            ///< [0, 10], 0 = 2-link model exact
  // [sweep]
  int seeds = 10;                       ///< replicates per cell, >= 1
  std::uint64_t master_seed = 1;
  std::vector<Variant> methods = allVariants();
  /// Everything else of a protocol run ([simulation], [identification]); the grid factors and
  /// the seed are set per job.
  ProtocolConfig base;
  /// The designed records of the "optimised" trajectories ([simulation] excitation_knee,
  /// excitation_both: `exoid excite` files).
  std::optional<sim::FourierSpec> optimised_knee, optimised_both;
  /// Where each key's value came from ("file:line:col" or "--flag"), for error messages.
  std::map<std::string, std::string> origin;

  SweepConfig();
  /// Throws SweepConfigError naming the key.
  void validate() const;
  std::vector<SweepCondition> conditions() const;
  int numCells() const { return static_cast<int>(conditions().size()); }
  /// Seed of job (cell, replicate): core::deriveSeed(core::deriveSeed(master_seed, c), replicate) with c
  /// the cell's index among the cells of one trajectories level (= cell with one level).
  std::uint64_t jobSeed(int cell, int replicate) const;
  /// The protocol run of a job.
  ProtocolConfig protocolFor(const SweepCondition& c, std::uint64_t seed) const;
  /// The resolved configuration (everything that changes results; not threads, out, shard).
  nlohmann::json toJson() const;
};

/// Reads a sweep TOML over the defaults. Unknown keys, wrong types and bad values throw
/// SweepConfigError with the key and file:line:col.
SweepConfig loadSweepConfig(const std::string& path);

nlohmann::json toJson(const SweepCondition& c);

}  // namespace exoid::experiments
