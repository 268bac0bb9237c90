#pragma once
// The one file form of a Fourier trajectory (core::FourierSeries), for every leg: what `exoid
// excite` writes as its design's "trajectory", a simulation sidecar records, a sweep's config.json
// keeps, and `exoid simulate --excitation`, sweeps and reproduce read:
//   {"f0_hz": 0.2, "locked_joints": 0,
//    "joints": [{"name": "hip", "offset_rad": -0.5, "cos_rad": [...], "sin_rad": [...]}, ...]}
// harmonic k (1-based) at index k - 1; the first `locked_joints` joints are held at their offsets.
#include "exoid/core/fourier_series.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace exoid::sim {

/// `joints` names the series' joints in order (one per joint).
nlohmann::json trajectoryJson(const core::FourierSeries& f, const std::vector<std::string>& joints);

struct NamedTrajectory {
  core::FourierSeries series;
  std::vector<std::string> joints;
};
/// Reads that form back, validated (FourierSeries::validate; the names non-empty and distinct);
/// throws std::invalid_argument naming the key ("joints[2].cos_rad: ...").
NamedTrajectory trajectoryFromJson(const nlohmann::json& j);

}  // namespace exoid::sim
