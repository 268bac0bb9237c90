#pragma once
// What a robot model lets anyone identify, before any record: `exoid identifiability --model`.
#include "exoid/core/tree_selection.hpp"

#include <iosfwd>
#include <string>
#include <vector>

namespace exoid::experiments {

/// Reads `model` (a built-in name, "apal" or "leg3", or an MJCF / URDF file), prints its chain,
/// its standard parameters' true values, the base parameters (rank, each combination in words and
/// its true value), what no torque shows and what is regrouped; writes the same as JSON to
/// json_out unless empty. Throws std::invalid_argument naming the file for a model exoid cannot take.
void reportModel(const std::string& model, const std::string& json_out, std::ostream& out,
                 const std::vector<std::string>& armature = {}, const core::ChainSelection& selection = {});

}  // namespace exoid::experiments
