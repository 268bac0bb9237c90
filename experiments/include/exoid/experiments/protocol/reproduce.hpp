#pragma once
// `exoid reproduce`: the paper's protocol once, on the simulated leg, reported next to the
// paper's own numbers and against ground truth.
#include "exoid/experiments/protocol/protocol.hpp"

#include <string>

namespace exoid::experiments {

/// Settings that resemble a real rig (documented in README): 17-bit encoders with 0.005 deg
/// noise, 0.5 N m torque noise, nominal pedestal compliance, the four-bar's mass, 10 s records.
ProtocolConfig defaultReproduceConfig();

struct ReproduceOutputs {
  bool plots = true;
  bool media = true;  ///< a still and a 3 s clip of trajectory 3 (when built with render)
  std::string dir;  ///< created if missing
  /// The clip's overlay shows the processed torque the methods fit (zero-phase filtered), not the
  /// raw record, whose sensor noise swings far wider than a model's error; true: the raw one.
  bool clip_raw_torque = false;
};

/// The designs exoid ships (exoid excite, seed 1) for the optimised-excitation arm.
std::string defaultKneeExcitationPath();
std::string defaultBothExcitationPath();

/// Writes report.md, results.json, estimates.csv, validation.csv, series_*.csv and figures. With
/// `optimised` (the same protocol and seed on designed identification records), also the
/// optimised-excitation arm: a side-by-side section in report.md, results.json
/// "optimised_excitation_arm", estimates_optimised.csv.
void writeReproduceOutputs(const ProtocolResult& r, const ReproduceOutputs& out, const ProtocolResult* optimised = nullptr);

/// Median of |v|: the median per-parameter relative error.
double medianAbs(const Eigen::VectorXd& v);

/// The verdict paragraph of the report, from the numbers alone.
std::string verdict(const ProtocolResult& r);

}  // namespace exoid::experiments
