#pragma once
// sim's serial chain (structure and true bodies, read from an MJCF or a URDF) as ident's
// ChainModel and its standard parameter vector: the one place the two meet.
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/ident/model/chain.hpp"
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/model/robot.hpp"
#include "exoid/ident/signals/preprocess.hpp"
#include "exoid/sim/serial_chain.hpp"

#include <Eigen/Core>

#include <functional>
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
  core::ChainSelection selection;  ///< the chain of the file (--base, --tip, --lock)
  sim::SerialChain chain;
  ident::ChainModel model;
  Eigen::VectorXd phi;
  ident::BaseParameters base;
  ident::Robot robot;  ///< model in its base parameters
};
/// The APAL leg's own pipeline applies (its X, the paper's protocol and rig): `name_or_path` names
/// the built-in leg's file, taken whole (no --base, --tip, --lock); any other model is a chain.
bool isApalLeg(const std::string& name_or_path, const core::ChainSelection& selection);

/// `selection` picks the chain out of a tree (--base, --tip, --lock).
LoadedChain loadChain(const std::string& name_or_path, const std::vector<std::string>& armature = {},
                      const core::ChainSelection& selection = {});

/// The chain in the base parameters of a moving base (a planar base: a link's inertia and its
/// joint's armature, which a still base regroups, separate), for records with base-motion terms.
/// They separate only through the base's pitch acceleration: an IMU's noise there biases the split
/// (docs/findings.md), so this is a choice (identify --moving-base-parameters), not the default.
/// Throws std::invalid_argument when none of `records` carries base-motion terms.
LoadedChain movingBase(LoadedChain loaded, const std::vector<ident::Dataset>& records, const ident::SignalOptions& signals);
/// Refuses data of another chain of loaded's file: `recorded` is the selection the data were
/// simulated with (a record's metadata 'chain_selection', a sidecar's model.selection). The same
/// joints held at another posture or hanging from another base move otherwise: fitted as loaded's,
/// estimates and truth would be silently wrong. A selection that changes only what is lumped into a
/// link (a branch held at another posture) passes: the fit takes the chain's kinematics alone.
/// Throws std::invalid_argument naming `source`, both selections and what differs.
void checkRecordedChain(const std::string& source, const std::string& recorded, const LoadedChain& loaded);
/// readLog's check_record for loaded's records: checkRecordedChain on their 'chain_selection'.
std::function<void(const std::string&, const ident::Dataset&)> recordOfChain(const LoadedChain& loaded);
/// The true base parameters of `loaded` from a chain simulation's sidecar: its standard
/// parameters, by name, through loaded's combination (a parameter the file lacks, an armature added
/// by --armature, is 0). Throws std::invalid_argument naming the file and what is missing, or the
/// sidecar's chain (its model.selection) when it is not loaded's.
Eigen::VectorXd truthFromSidecar(const std::string& path, const LoadedChain& loaded);

}  // namespace exoid::experiments
