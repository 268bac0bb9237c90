#pragma once
// A robot as identification sees it: a serial chain (chain.hpp) and the parameters its joint
// torques are fitted in, tau = Y(q, qd, qdd) theta with theta = combination phi, one basis of the
// chain's base parameters (phi: its standard parameters). Every part of the pipeline (processing,
// estimators, consistency, closed loop, excitation) takes a Robot, whatever the leg.
//
// Any chain is fitted in its base parameters (base_parameters.hpp: Y is the standard regressor's
// independent columns). The 2-link leg (hip, knee) is fitted in the paper's X = [Mxt, Myt, Jt,
// fc1, fv1, Mxs, Mys, Js, fc2, fv2] (and Ia2, the knee's armature): the same span, named as the
// paper names it, its rows from the hand-written regressor (leg/regressor.hpp), the fast path.
#include "exoid/ident/leg/regressor.hpp"
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/ident/model/chain.hpp"
#include "exoid/ident/model/newton_euler.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace exoid::ident {

struct Robot {
  ChainModel chain;
  /// The parameters fitted: rank, names, combination (theta = combination * phi). The chain's
  /// base parameters carry `independent` (their columns of the standard regressor); a named basis
  /// (the 2-link leg's X) leaves it empty: its rows come from its own regressor.
  BaseParameters basis;
  std::vector<std::string> units;  ///< SI unit of each parameter ("kg m", ...); "" where mixed
  /// For each joint's equation, the parameters whose regressor columns are not zero by
  /// construction, ascending: the processing computes and filters only those.
  std::vector<std::vector<int>> joint_columns;
  /// The parameters that are Coulomb coefficients (their columns are sgn(qd)).
  std::vector<int> coulomb;
  /// The 2-link leg: its rows from the hand-written regressor with these constants.
  std::optional<LegConstants> two_link;
  bool knee_armature = false;  ///< two_link only: Ia2 is parameter kKneeArmature

  int dof() const { return chain.dof(); }
  int parameters() const { return basis.rank; }
  const std::vector<std::string>& names() const { return basis.names; }
  std::vector<std::string> jointNames() const { return chain.jointNames(); }
  /// Sum of joint_columns' sizes: the columns the processing filters, besides the torques.
  Eigen::Index structuralColumnCount() const;
};

/// The kind of quantity a parameter is: its leading standard parameter's (a base parameter's name,
/// the first one of a named basis's combination), which says what motion informs it.
enum class ParameterKind { kMass, kFirstMoment, kInertia, kCoulomb, kViscous, kArmature };
std::vector<ParameterKind> parameterKinds(const Robot& robot);

/// The chain in its base parameters. Throws std::invalid_argument on an invalid model or options.
Robot chainRobot(const ChainModel& model, const BaseParameterOptions& options = {});

/// The 2-link leg's chain: hip and knee about +y (x anterior, z up), links hanging along -z at
/// q = 0, the knee c.thigh_length_m below the hip, friction on both joints, gravity -g z.
ChainModel twoLinkChain(const LegConstants& c, bool knee_armature = false);
/// twoLinkChain in the paper's X (docs/paper.md, "Modelling facts": Mx = -mz, My = -mx, J = Iyy
/// about the joint, the shank's mass carried at Lt by the thigh), Ia2 = knee.Ia when asked.
Robot twoLinkLeg(const LegConstants& c, bool knee_armature = false);

/// What robotRowsInto reuses between calls.
struct RobotWorkspace {
  ChainRegressorWorkspace chain;
  Eigen::MatrixXd Y;    ///< the standard regressor at the state (chains)
  Eigen::VectorXd phi;  ///< theta as standard parameters (robotTorque)
};

/// The dof x parameters() rows at one state (joint-relative rates), into `out` (already sized).
/// Throws std::invalid_argument if a vector's size is not dof().
void robotRowsInto(const Robot& robot, const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& qd,
                   const Eigen::Ref<const Eigen::VectorXd>& qdd, const ChainBaseMotion& base, RobotWorkspace& work,
                   Eigen::Ref<Eigen::MatrixXd> out);

/// The rows of the joints from `first_moving` down at o.samples random states (q uniform in
/// [-pi, pi], qd in [-3, 3] rad/s, qdd in [-30, 30] rad/s^2, from o.seed and first_moving), the
/// joints above it still: at held_at_rad (one angle each) when given, else at random angles. What
/// a stage's record can determine is what these rows determine: the structure, not data.
Eigen::MatrixXd heldJointRows(const Robot& robot, Eigen::Index first_moving, const BaseParameterOptions& o,
                              const Eigen::VectorXd& held_at_rad = {});

/// tau = Y(q, qd, qdd) theta at one state on a still base under the chain's gravity (a model's
/// inverse dynamics: its closed loop, its feedforward). The 2-link leg's from its hand-written rows.
Eigen::VectorXd robotTorque(const Robot& robot, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                            const Eigen::VectorXd& theta, RobotWorkspace& work);

/// Sample i's base motion of signals whose base columns are the planar IMU's (JointSignals::base:
/// specific force x and z, pitch rate and acceleration about y, in the chain's base frame); a
/// still base under the chain's gravity when s has none.
ChainBaseMotion baseMotionAt(const Robot& robot, const JointSignals& s, Eigen::Index i);

/// Every sample's structurally nonzero columns into `out` (s.size() x structuralColumnCount()):
/// joint 0's joint_columns, then joint 1's, ... Throws std::invalid_argument on sizes that disagree.
void structuralColumns(const Robot& robot, const JointSignals& s, Eigen::Ref<Eigen::MatrixXd> out);

/// s.size() x dof: the torques theta predicts along the signals (a chain's by Newton-Euler, in
/// chunks on `threads`, 0 = the machine's cores: the same bytes whatever the number).
Eigen::MatrixXd predictTorques(const Robot& robot, const JointSignals& s, const Eigen::VectorXd& theta, int threads = 1);

}  // namespace exoid::ident
