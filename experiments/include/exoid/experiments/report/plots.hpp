#pragma once
// Figures are drawn by small matplotlib scripts (experiments/plots/*.py, run with Debian's
// /usr/bin/python3 and python3-matplotlib) from the CSV/JSON the commands write.
#include <string>
#include <vector>

namespace exoid::experiments {

/// Runs experiments/plots/<script> with the arguments; throws std::runtime_error with the
/// script's stderr when it fails or when python3/matplotlib is missing.
void runPlotScript(const std::string& script, const std::vector<std::string>& args);

}  // namespace exoid::experiments
