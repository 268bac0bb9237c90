#pragma once
// Batch least squares (paper Eq. 5) by column-pivoted QR, with rank and conditioning reported.
#include "exoid/ident/estimators/summary.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace exoid::ident {

struct LsOptions {
  /// A column is unidentifiable when its pivoted |R_kk| < rank_tolerance * |R_00| after scaling
  /// every column to unit norm. Range (0, 1). Default 1e-8: far above roundoff (~1e-15 * cond)
  /// and below any usable conditioning (cond > 1e8 means parameters are not separable).
  double rank_tolerance = 1e-8;
  /// Full rank but condition number (scaled columns) above this: Status kIllConditioned, not
  /// usable. The relative error of a least-squares estimate is bounded by cond x the relative
  /// error of the torque it fits, so above 1e5 a 0.1 % torque error (a good sensor's accuracy,
  /// or the model's own error) can move the estimate by 100 %: the numbers mean nothing even
  /// when they look plausible. The paper's knee record has ~250. Range > 1. Every method's
  /// estimate is held to the same bound (ident::estimate).
  double max_condition = 1e5;
  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

struct LsResult {
  Eigen::VectorXd x;  ///< estimate; on rank deficiency the basic solution (unidentifiable = 0)
  Eigen::Index rank = 0;
  /// Condition number (ratio of extreme singular values) of the column-scaled regressor.
  double condition_number = 0.0;
  std::vector<Eigen::Index> unidentifiable;  ///< column indices beyond the numerical rank
  /// Each column's R^2 on the others, 1 - 1 / [(Hs^T Hs)^-1]_jj for unit columns Hs (a model error
  /// along it is amplified 1 / sqrt(1 - R^2) times); all 1 on rank deficiency.
  Eigen::VectorXd collinearity_r2;
  /// [(Hs^T Hs)^-1]_jj = 1 / (1 - R^2_j), each column's variance inflation (its variance over that
  /// of an orthogonal unit column); all infinity on rank deficiency.
  Eigen::VectorXd variance_inflation;
  double residual_rms = 0.0;                 ///< sqrt(mean((y - H x)^2))
  Summary summary;
};

/// min ||y - H x||_2. Status kRankDeficient (message names the columns) when rank < cols.
/// Throws std::invalid_argument on size mismatch, non-finite input or fewer rows than columns.
LsResult solveLeastSquares(const Eigen::MatrixXd& H, const Eigen::VectorXd& y,
                           const LsOptions& options = {});

/// Condition number (ratio of extreme singular values) of H with its columns scaled to unit
/// norm; infinity when a column is a combination of the others. H needs rows >= cols.
double scaledConditionNumber(const Eigen::MatrixXd& H);
/// The message of Status kIllConditioned: the condition, the bound and what it means.
std::string illConditionedMessage(double condition, double max_condition);

/// Column scales used for conditioning: 1 / ||column||_2 (1 for a zero column).
Eigen::VectorXd columnScales(const Eigen::MatrixXd& H);

}  // namespace exoid::ident
