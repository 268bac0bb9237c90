#pragma once
// The subcommands. Each adds itself to the app; its callback throws on error (cli.cpp maps
// exceptions to messages and exit codes).
#include <CLI/CLI.hpp>

#include <stdexcept>

namespace exoid::experiments {

/// Raised when a run finished but its result must not be trusted (e.g. rank deficiency):
/// outputs are written, the exit code is 3.
class UnusableResult : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

void addIdentifyCommand(CLI::App& app);
void addIdentifiabilityCommand(CLI::App& app);
#ifdef EXOID_WITH_MUJOCO
void addSimulateCommand(CLI::App& app);
void addTruthCommand(CLI::App& app);
void addReproduceCommand(CLI::App& app);
void addSweepCommand(CLI::App& app);
void addMergeCommand(CLI::App& app);
void addExciteCommand(CLI::App& app);
#endif
#ifdef EXOID_WITH_RENDER
void addRenderCommand(CLI::App& app);
#endif

}  // namespace exoid::experiments
