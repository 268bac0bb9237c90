#pragma once
// The reference a tracking controller followed, sampled on a uniform grid: angles and their first
// two derivatives, samples x joints. One type for the 2-link leg (MatrixX2d: leg/closed_loop.hpp)
// and any chain (MatrixXd: model/chain_closed_loop.hpp), so both are checked and differentiated
// alike.
#include <Eigen/Core>

namespace exoid::ident {

template <class Matrix>
struct SampledReference {
  Eigen::VectorXd t_s;
  Matrix q_rad, qd_radps, qdd_radps2;
  Eigen::Index size() const { return t_s.size(); }
  /// Throws std::invalid_argument on size mismatch, < 5 samples, time that does not increase
  /// uniformly (within 0.1 % of its mean step) or a value that is not finite.
  void validate() const;
  /// From recorded reference angles: five-point central differences (exact to O(dt^4) for the
  /// smooth references of planned trajectories); validated.
  static SampledReference fromAngles(const Eigen::VectorXd& t_s, const Matrix& q_ref_rad);
};

extern template struct SampledReference<Eigen::MatrixX2d>;
extern template struct SampledReference<Eigen::MatrixXd>;

}  // namespace exoid::ident
