#pragma once
// Figures are drawn by small matplotlib scripts (experiments/plots/*.py, run with Debian's
// /usr/bin/python3 and python3-matplotlib) from the CSV/JSON the commands write.
#include "exoid/ident/signals/processing.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace exoid::experiments {

/// Runs experiments/plots/<script> with the arguments; throws std::runtime_error with the
/// script's stderr when it fails or when python3/matplotlib is missing.
void runPlotScript(const std::string& script, const std::vector<std::string>& args);

/// identify --plot on any leg: `png`, each joint's torque in `shown` (a record processed as the
/// fit's) against the torque `theta` predicts (shown.W theta) and their difference, and the series
/// beside it (<png stem>_series.csv: t_s, tau_<joint>, tau_<joint>_predicted, %.9g); says so on stdout.
void plotTorqueFit(const std::string& png, const std::vector<std::string>& joints, const ident::RecordRows& shown,
                   const Eigen::VectorXd& theta, const std::string& title);

}  // namespace exoid::experiments
