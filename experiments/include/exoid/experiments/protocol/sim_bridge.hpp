#pragma once
// Where sim meets ident: simulated tables as datasets, exact signals, and the best-fit truth.
#include "exoid/ident/model/closed_loop.hpp"
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/leg/regressor.hpp"
#include "exoid/sim/simulate.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace exoid::experiments {

/// The simulated table as the dataset ident reads from CSV (same columns, same metadata).
ident::Dataset toDataset(const sim::SimResult& r);

/// Exact signals of a simulated dataset: q/qd/qdd_*_true and the given torque columns
/// ("tau_hip_true"/"tau_knee_true" or "tau_hip_ideal"/"tau_knee_ideal").
ident::JointSignals exactSignals(const ident::Dataset& d, const std::string& tau_suffix);

ident::ParamVector toParamVector(const sim::ParamArray& x);
ident::LegConstants constantsOf(const sim::Truth& t);

/// The best-fit truth of a record: LS of the exact, noise-free, vibration-free (ideal) torques
/// at the exact states. Blocks the record cannot identify (e.g. the thigh when the hip is
/// locked) are taken from `fallback` and listed in `from_fallback`.
struct BestFit {
  ident::ParamVector x;
  std::vector<std::string> from_fallback;
  double residual_rms_Nm = 0.0;  ///< of the fit, both equations
};
BestFit bestFitTruth(const ident::Dataset& d, const ident::LegConstants& c, const ident::ParamVector& fallback);

/// Share of each torque's variance above `f_hz` (Welch, ident::varianceFractionAbove): how much
/// of a record is high-frequency content (controller chatter, noise) rather than motion. Keys:
/// the torque columns present (tau_hip, tau_knee, and tau_*_true, tau_*_ideal when recorded).
std::map<std::string, double> torqueVarianceAbove(const ident::Dataset& d, double f_hz = 10.0);

/// The full sidecar: sim's (settings, rigid truth, band, stats) plus the best-fit truth and the
/// torques' variance share above 10 Hz.
nlohmann::json simulationSidecar(const sim::SimResult& r, const ident::Dataset& d);

/// exoid's simulated controller as IDIM-IV models it: its PID gains, model feedforward when
/// cfg.feedforward, the hip locked on the knee-only trajectories.
ident::Controller controllerOf(const sim::SimConfig& cfg, bool hip_locked);

/// Flags of `exoid simulate` (shared with render and the experiments that simulate). With
/// choose_trajectory, also --trajectory and the Fourier-series flags (the protocol runs 1-4).
void addSimOptions(CLI::App& app, sim::SimConfig& c, bool choose_trajectory = true);

}  // namespace exoid::experiments
