#pragma once
// The reference a tracking controller followed, sampled on a uniform grid: angles and their first
// two derivatives, samples x joints, for any robot.
#include <Eigen/Core>

namespace exoid::ident {

struct SampledReference {
  Eigen::VectorXd t_s;
  Eigen::MatrixXd q_rad, qd_radps, qdd_radps2;
  Eigen::Index size() const { return t_s.size(); }
  /// Throws std::invalid_argument on size mismatch, < 5 samples, time that does not increase
  /// uniformly (within 0.1 % of its mean step) or a value that is not finite.
  void validate() const;
  /// From recorded reference angles: five-point central differences (exact to O(dt^4) for the
  /// smooth references of planned trajectories); validated.
  static SampledReference fromAngles(const Eigen::VectorXd& t_s, const Eigen::MatrixXd& q_ref_rad);
};

}  // namespace exoid::ident
