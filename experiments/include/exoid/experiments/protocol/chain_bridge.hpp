#pragma once
// sim's serial chain (structure and true bodies, read from an MJCF or a URDF) as ident's
// ChainModel and its standard parameter vector: the one place the two meet.
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/ident/model/chain.hpp"
#include "exoid/ident/model/robot.hpp"
#include "exoid/sim/serial_chain.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace exoid::experiments {

/// The chain's structure; every joint with friction, armature where the model has any.
ident::ChainModel chainModel(const sim::SerialChain& chain);
/// The model with an armature parameter on these joints (names, or "all") although the file
/// gives none (a URDF never does). Throws std::invalid_argument naming an unknown joint.
ident::ChainModel withArmature(ident::ChainModel model, const std::vector<std::string>& joints);
/// The true standard parameters in chainModel(chain)'s layout.
Eigen::VectorXd standardParameters(const sim::SerialChain& chain);
/// The same in the layout of `model` (the chain's, e.g. with armature added where the file has
/// none: its value 0).
Eigen::VectorXd standardParameters(const sim::SerialChain& chain, const ident::ChainModel& model);

/// A robot file read for the chain commands: its path ('apal', 'leg3' or a file resolved), the
/// chain, ident's model (with armature added on `armature`'s joints), the file's standard
/// parameters in that model's layout, and its base parameters.
struct LoadedChain {
  std::string path;
  sim::SerialChain chain;
  ident::ChainModel model;
  Eigen::VectorXd phi;
  ident::BaseParameters base;
  ident::Robot robot;  ///< model in its base parameters
};
LoadedChain loadChain(const std::string& name_or_path, const std::vector<std::string>& armature = {});

}  // namespace exoid::experiments
