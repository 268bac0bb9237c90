#pragma once
// `exoid reproduce`: the paper's protocol once, on the simulated leg, reported next to the
// paper's own numbers and against ground truth.
#include "exoid/experiments/protocol.hpp"

#include <string>

namespace exoid::experiments {

/// Settings that resemble a real rig (documented in README): 17-bit encoders with 0.005 deg
/// noise, 0.5 N m torque noise, nominal pedestal compliance, the four-bar's mass, 10 s records.
ProtocolConfig defaultReproduceConfig();

struct ReproduceOutputs {
  bool plots = true;
  bool media = true;  ///< a still and a 3 s clip of trajectory 3 (when built with render)
  std::string dir;  ///< created if missing
};

/// Writes report.md, results.json, estimates.csv, validation.csv, series_*.csv and figures.
void writeReproduceOutputs(const ProtocolResult& r, const ReproduceOutputs& out);

/// The verdict paragraph of the report, from the numbers alone.
std::string verdict(const ProtocolResult& r);

}  // namespace exoid::experiments
