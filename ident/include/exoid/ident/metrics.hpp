#pragma once
// Scores: validation torque error and parameter error against a truth vector.
#include <Eigen/Core>

namespace exoid::ident {

/// Statistics of |measured - predicted| (N m), as the paper reports them (mean +- std).
struct TorqueErrorStats {
  double mean_abs = 0.0;
  double std_abs = 0.0;  ///< population std of |error|
  double rms = 0.0;
  double max_abs = 0.0;
};
TorqueErrorStats torqueError(const Eigen::Ref<const Eigen::VectorXd>& measured,
                             const Eigen::Ref<const Eigen::VectorXd>& predicted);

struct ParamError {
  Eigen::VectorXd abs;  ///< estimate - truth
  Eigen::VectorXd rel;  ///< (estimate - truth) / |truth|; 0 where truth is 0 and estimate equal
  double norm_rel = 0.0;  ///< ||estimate - truth||_2 / ||truth||_2
  double max_abs_rel = 0.0;  ///< max |rel|
};
/// Throws std::invalid_argument on size mismatch or an all-zero truth.
ParamError paramError(const Eigen::Ref<const Eigen::VectorXd>& estimate,
                      const Eigen::Ref<const Eigen::VectorXd>& truth);

}  // namespace exoid::ident
