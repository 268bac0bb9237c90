#pragma once
// The grid of `exoid sweep`: read from TOML (experiments/configs/default_sweep.toml), overridden
// by flags, validated before any work starts. Cells are the full factorial of the grid lists;
// a job is (cell, replicate) and its seed derives from (master seed, cell, replicate) only, where
// the identification trajectories (paper | optimised) do not count as part of the cell: a paper
// cell and its optimised twin share their seeds (common random numbers), so they pair.
#include "exoid/core/tree_selection.hpp"
#include "exoid/experiments/protocol/protocol.hpp"
#include "exoid/ident/estimators/methods.hpp"
#include "exoid/sim/motor_rig.hpp"
#include "exoid/sim/trajectory_json.hpp"

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

/// One grid cell: the factor levels that vary between cells. A chain model's cells have no
/// vibration or cylinder (0) and its trajectories are "optimised" (one design for the sweep) or
/// "default" (the simulator's default motion of each run's seed).
struct SweepCondition {
  double torque_noise_Nm = 0.0;
  double angle_noise_deg = 0.0;
  double quantisation_deg = 0.0;
  double vibration_level = 0.0;
  double cylinder_mass_scale = 0.0;
  /// Play between each joint and its encoder, deg (a motor-side encoder behind a gear's backlash:
  /// angle content the torque does not follow; `exoid simulate --encoder-backlash-deg`). The APAL
  /// leg's rig only.
  double encoder_backlash_deg = 0.0;
  /// The identification records: "paper" (trajectories 1 and 3) or "optimised" (the designs of
  /// [simulation] excitation_knee / excitation_both). Validation stays on trajectories 2 and 4.
  std::string trajectories = "paper";
};

struct SweepConfig {
  // [grid]: every combination is a cell (order: trajectories, encoder backlash, cylinder,
  // vibration, angle noise, quantisation, torque noise; torque noise varies fastest).
  std::vector<std::string> trajectories{"paper"};               ///< "paper", "optimised"
  std::vector<double> torque_noise_Nm{0.0, 0.1, 0.5, 1.0, 2.0};  ///< >= 0
  std::vector<double> angle_noise_deg{0.005};                   ///< >= 0
  std::vector<double> quantisation_deg{360.0 / 131072.0};       ///< >= 0 (0 = none)
  std::vector<double> vibration_level{0.0, 1.0, 2.0};           ///< [0, 20], 0 = welded mount
  std::vector<double> cylinder_mass_scale{0.0, 1.0};            ///< [0, 10], 0 = 2-link model exact
  std::vector<double> encoder_backlash_deg{0.0};                ///< [0, 89], 0 = none; the APAL leg only
  // [sweep]
  int seeds = 10;                       ///< replicates per cell, >= 1
  std::uint64_t master_seed = 1;
  std::vector<Variant> methods = allVariants();
  /// Everything else of a protocol run ([simulation], [identification]); the grid factors and
  /// the seed are set per job.
  ProtocolConfig base;
  /// The designed records of the "optimised" trajectories ([simulation] excitation_knee,
  /// excitation_both: `exoid excite` files).
  std::optional<core::FourierSeries> optimised_knee, optimised_both;
  /// [sweep] model: empty or "apal" = the APAL leg (the paper's protocol); "leg3" or an MJCF or
  /// URDF file = any serial chain (a chain sweep: robot_sweep.hpp).
  std::string model;
  /// The chain's file (sim::modelPathFor(model)); empty for the APAL leg.
  std::string chain_model_path;
  /// [sweep] base, tip, lock: a URDF tree's chain, as identify's --base, --tip, --lock.
  core::ChainSelection chain_selection;
  /// A chain sweep's methods (methods is the APAL leg's).
  std::vector<ident::Method> chain_methods{ident::Method::kLs, ident::Method::kRls, ident::Method::kPso,
                                           ident::Method::kRlsPso, ident::Method::kLad, ident::Method::kIvBand,
                                           ident::Method::kIdimIv};
  /// A chain sweep's "optimised" record ([simulation] excitation: an `exoid excite --model` file);
  /// when absent, runSweep designs one (exoid excite --model's defaults, seed from master_seed).
  std::optional<sim::NamedTrajectory> chain_design;
  /// Where each key's value came from ("file:line:col" or "--flag"), for error messages.
  std::map<std::string, std::string> origin;

  SweepConfig();
  bool isChain() const { return !chain_model_path.empty(); }
  /// Sets the model (origin: "--model" or file:line:col) and, for a chain, its grid's defaults
  /// (vibration and cylinder 0, trajectories "optimised", where the file did not set them).
  /// Throws SweepConfigError naming the key for a model that cannot be read.
  void setModel(const std::string& name_or_path, const std::string& origin);
  /// Parses the method names for this model (Variants for the APAL leg, ident::Method for a
  /// chain); origin names the key or flag in errors.
  void setMethods(const std::vector<std::string>& names, const std::string& origin);
  /// The method names of the sweep, in order.
  std::vector<std::string> methodNames() const;
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

 private:
  void validateApal() const;
  nlohmann::json chainJson() const;
};

/// Reads a sweep TOML over the defaults. Unknown keys, wrong types and bad values throw
/// SweepConfigError with the key and file:line:col. model_override (--model) replaces the file's
/// [sweep] model before the methods and the grid are checked against it.
SweepConfig loadSweepConfig(const std::string& path, const std::string& model_override = "");

nlohmann::json toJson(const SweepCondition& c);
/// A condition's CSV columns (every grid factor, as conditionCsvHeader names them), for every
/// sweep's runs.csv and summary.csv.
std::string conditionCsv(const SweepCondition& c);
inline constexpr const char* kConditionCsvHeader =
    "torque_noise_Nm,angle_noise_deg,quantisation_deg,vibration_level,cylinder_mass_scale,encoder_backlash_deg,trajectories";

}  // namespace exoid::experiments
