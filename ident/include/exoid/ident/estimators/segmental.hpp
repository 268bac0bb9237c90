#pragma once
// The paper's segmental strategy (Fig. 5, Eq. 9), for any robot: distal joints first, proximal
// joints locked, stage by stage down the chain. A stage is the records in which joints
// first_joint .. tip move and the joints above are locked; it fits the parameter combinations its
// moving joints determine that earlier (more distal) stages left open, with the combinations
// already identified moved to the torque side (the paper's T1' = T1 - H_hip(6:10) X(6:10),
// generalised). The last stage, every joint moving, takes what is left. On the APAL leg: the knee
// parameters Mxs .. fv2 from the knee record (hip fixed), then Mxt .. fv1 from the hip equation of
// a record where both joints swing.
//
// Which combinations a stage determines is computed from the model, not from the data (as base
// parameters are, Gautier 1990): the stage's rows at random states with the locked joints' rates
// and accelerations zero, projected away from what is known, their right singular vectors above
// the tolerance. Combinations that are whole parameters (the APAL leg's every stage) are fitted as
// themselves, so a search box (PSO, RLS-PSO) is the paper's; where a lock makes two parameters act
// alike (a link's inertia and its joint's armature when the joints above are locked) the stage
// fits their sum and a later stage separates them. A stage fits only the equations that involve
// its unknowns (the APAL leg's last stage: the hip's).
#include "exoid/ident/estimators/methods.hpp"
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/ident/model/robot.hpp"
#include "exoid/ident/signals/processing.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace exoid::ident {

struct SegmentalStage {
  /// Joints first_joint .. dof - 1 move; the joints above it are locked (their equations, which
  /// the lock carries, are not fitted). 0: every joint moves.
  Eigen::Index first_joint = 0;
  RecordRows record;  ///< the stage's records' rows (every joint's, as processRecord gives)
};

/// What one stage fits, given what the stages before it found: y = H x over its unknowns.
struct StageProblem {
  Eigen::Index first_joint = 0;
  /// The combinations this stage identifies (robot parameters x k, unit columns) and each in words
  /// ("Js", "0.707 (foot.Iyy) + 0.707 (ankle.Ia)", ...).
  Eigen::MatrixXd directions;
  std::vector<std::string> names;
  /// The parameters themselves when every direction is one (the APAL leg's stages); else empty.
  std::vector<int> parameters;
  std::vector<Eigen::Index> rows;  ///< the record's rows fitted (the equations involving the unknowns)
  Eigen::MatrixXd H;
  Eigen::VectorXd y;  ///< the torque with what is known subtracted
  /// The robot's parameters with the known combinations in, theta = known + directions x.
  Eigen::VectorXd known;
  /// x back into the robot's parameters (the known ones and this stage's; zero elsewhere).
  Eigen::VectorXd theta(const Eigen::VectorXd& x) const;
};

/// The stages' combinations, from the robot's structure. Throws std::invalid_argument for an empty
/// or misordered list (stages go distal first: first_joint non-increasing), a joint out of range, a
/// stage that identifies nothing new, or stages that leave combinations unidentified (naming them).
class SegmentalPlan {
 public:
  SegmentalPlan(const Robot& robot, const std::vector<Eigen::Index>& first_joints, const BaseParameterOptions& structure = {});
  int stages() const { return static_cast<int>(directions_.size()); }
  /// Stage s's problem on its record's rows, the earlier stages' values in `found` (one vector of
  /// each earlier stage's x, in order).
  StageProblem problem(int s, const RecordRows& record, const std::vector<Eigen::VectorXd>& found) const;
  /// All parameters from every stage's x.
  Eigen::VectorXd assemble(const std::vector<Eigen::VectorXd>& found) const;

 private:
  const Robot& robot_;
  std::vector<Eigen::Index> first_;
  std::vector<Eigen::MatrixXd> directions_;
};

struct StageResult {
  StageProblem problem;  ///< what was fitted (H and y cleared: the rows are the caller's)
  Estimate estimate;     ///< the method's result over the stage's combinations (x: their values)
};

struct SegmentalResult {
  Eigen::VectorXd theta;  ///< every parameter, assembled from the stages
  std::vector<StageResult> stages;
  bool usable() const;  ///< every stage's estimate is usable (full rank, conditioned)
};

/// Runs `method` stage by stage. Throws as SegmentalPlan does, or for a record of another robot.
SegmentalResult identifySegmental(const Robot& robot, const std::vector<SegmentalStage>& stages, Method method,
                                  const MethodOptions& options, const BaseParameterOptions& structure = {});

}  // namespace exoid::ident
