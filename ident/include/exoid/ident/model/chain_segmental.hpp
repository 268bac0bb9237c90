#pragma once
// The paper's segmental strategy for any serial chain: distal joints first, proximal joints
// locked, stage by stage down the chain. A stage is the records in which joints first_joint ..
// tip move and the joints above are locked; it fits the equations of its moving joints for the
// base-parameter combinations they determine that earlier (more distal) stages left open, with the
// combinations already identified moved to the torque side (the paper's Eq. 9: T1' = T1 -
// H_hip(6:10) X(6:10), generalised). The last stage, all joints moving, takes what is left.
//
// Which combinations a stage determines is computed from the model, not from the data (as the base
// parameters are, Gautier 1990): the stage's rows at random states with the locked joints' rates
// and accelerations zero, projected away from what is known, their right singular vectors above
// the base parameters' tolerance. On a stage whose combinations are whole base parameters (the
// APAL leg's knee stage: Mxs, Mys, Js, fc2, fv2) those parameters are the stage's unknowns, so a
// search box (PSO, RLS-PSO) is the paper's; where a lock makes two parameters act alike (a link's
// inertia and its joint's armature when the joints above are locked) the stage fits their sum
// and a later stage separates them.
#include "exoid/ident/estimators/methods.hpp"
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/ident/model/chain.hpp"
#include "exoid/ident/model/chain_processing.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace exoid::ident {

struct ChainStage {
  /// Joints first_joint .. dof - 1 move; the joints above it are locked (their equations, which
  /// the lock carries, are not fitted). 0: every joint moves.
  Eigen::Index first_joint = 0;
  ChainRecord record;  ///< the stage's records' rows (every joint's, as processChainRecord gives)
};

struct ChainStageResult {
  Eigen::Index first_joint = 0;
  Eigen::Index rows = 0;  ///< equations fitted
  /// The combinations this stage identified (base-parameter space, one per column, unit norm) and
  /// each in words ("Js", "0.707 foot.Iyy + 0.707 ankle.Ia", ...).
  Eigen::MatrixXd directions;
  std::vector<std::string> names;
  Estimate estimate;  ///< the method's result over those combinations (x: their values)
};

struct ChainSegmentalResult {
  Eigen::VectorXd beta;  ///< all base parameters, assembled from the stages
  std::vector<ChainStageResult> stages;
};

/// Runs `method` stage by stage (stages ordered distal first: first_joint non-increasing). Throws
/// std::invalid_argument for an empty or misordered list, a record of another dof, a stage that
/// identifies nothing new, or stages that leave combinations unidentified (naming them).
ChainSegmentalResult identifyChainSegmental(const ChainModel& model, const BaseParameters& base,
                                            const std::vector<ChainStage>& stages, Method method,
                                            const MethodOptions& options, const BaseParameterOptions& structure = {});

}  // namespace exoid::ident
