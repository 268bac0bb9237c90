#pragma once
// Batch least squares (paper Eq. 5) by column-pivoted QR, with rank and conditioning reported.
#include "exoid/ident/summary.hpp"

#include <Eigen/Core>

#include <vector>

namespace exoid::ident {

struct LsOptions {
  /// A column is unidentifiable when its pivoted |R_kk| < rank_tolerance * |R_00| after scaling
  /// every column to unit norm. Range (0, 1). Default 1e-8: far above roundoff (~1e-15 * cond)
  /// and below any usable conditioning (cond > 1e8 means parameters are not separable).
  double rank_tolerance = 1e-8;
  /// Full rank but condition number (scaled columns) above this: the message warns that the
  /// estimate is dominated by noise and model error (kept kConverged: on exact data it is still
  /// right). Range > 1. Default 1e5 (the paper's knee record has ~250; 1e5 amplifies a 0.1 %
  /// torque error to ~100 %).
  double warn_condition = 1e5;
  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

struct LsResult {
  Eigen::VectorXd x;  ///< estimate; on rank deficiency the basic solution (unidentifiable = 0)
  Eigen::Index rank = 0;
  /// Condition number (ratio of extreme singular values) of the column-scaled regressor.
  double condition_number = 0.0;
  std::vector<Eigen::Index> unidentifiable;  ///< column indices beyond the numerical rank
  double residual_rms = 0.0;                 ///< sqrt(mean((y - H x)^2))
  Summary summary;
};

/// min ||y - H x||_2. Status kRankDeficient (message names the columns) when rank < cols.
/// Throws std::invalid_argument on size mismatch, non-finite input or fewer rows than columns.
LsResult solveLeastSquares(const Eigen::MatrixXd& H, const Eigen::VectorXd& y,
                           const LsOptions& options = {});

/// Column scales used for conditioning: 1 / ||column||_2 (1 for a zero column).
Eigen::VectorXd columnScales(const Eigen::MatrixXd& H);

}  // namespace exoid::ident
