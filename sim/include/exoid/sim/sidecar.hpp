#pragma once
// The JSON sidecar of a simulated dataset: provenance, every setting, the truths, statistics.
#include "exoid/sim/simulate.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace exoid::sim {

/// Every field of the configuration, SI units as in the struct.
nlohmann::json configJson(const SimConfig& config);
/// X as {"Mxt": ..., ...}.
nlohmann::json paramsJson(const ParamArray& x);
/// The sidecar: {"format", "exoid_version", "mujoco_version", "model": {path, fnv1a64, bytes},
/// "seed", "settings", "columns", "truth": {"rigid", "lumped_band", "thigh_length_m",
/// "gravity_mps2", "friction"}, "stats"}. The caller may add e.g. "truth"/"best_fit".
nlohmann::json sidecar(const SimResult& result, const std::string& exoid_version);
/// Writes JSON (2-space indent) atomically.
void writeJson(const nlohmann::json& j, const std::string& path);
/// A record's sidecar beside it: the same name with .json for its extension.
std::string sidecarPathOf(const std::string& csv_path);

}  // namespace exoid::sim
