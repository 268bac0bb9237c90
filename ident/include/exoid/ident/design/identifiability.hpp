#pragma once
// What a record can identify, before anyone runs an experiment: rank and conditioning, which
// parameters are not identifiable, Cramer-Rao standard deviations at a torque noise level, and
// collinearity of each column with the others.
#include "exoid/ident/estimators/noise_covariance.hpp"

#include <Eigen/Core>

#include <vector>

namespace exoid::ident {

struct IdentifiabilityReport {
  Eigen::Index rows = 0;
  Eigen::Index rank = 0;
  double condition_number = 0.0;  ///< of the column-scaled regressor (inf when rank deficient)
  std::vector<Eigen::Index> unidentifiable;  ///< columns beyond the numerical rank
  /// Cramer-Rao lower bound of each parameter's std for white torque noise of std sigma:
  /// sigma * sqrt(diag((H^T H)^-1)) (the LS covariance, efficient for Gaussian noise). Inf for
  /// an unidentifiable column.
  Eigen::VectorXd crb_std;
  /// crb_std / |reference|: relative std, reference = the LS estimate unless given.
  Eigen::VectorXd crb_rel_std;
  /// Uncentred R^2 of each column regressed on all others (no intercept, like the model):
  /// 1 - 1 / (||h_j||^2 [(H^T H)^-1]_jj). Near 1 = nearly collinear. 1 when unidentifiable.
  Eigen::VectorXd collinearity_r2;
};

/// `reference` (size = H.cols()) scales the relative stds: the true or nominal parameters. An
/// empty vector uses the LS estimate of y = H x, which misleads when that estimate is itself
/// wrong (a huge estimate makes any std look small); NaN entries leave those relative stds NaN. noise_sigma >= 0 (N m). Throws std::invalid_argument on bad sizes.
IdentifiabilityReport analyzeIdentifiability(const Eigen::MatrixXd& H, const Eigen::VectorXd& y,
                                             double noise_sigma,
                                             const Eigen::VectorXd& reference = Eigen::VectorXd());

/// The same report with the Cramer-Rao std of the noise as it reaches the fit: `channels` hold the
/// rows of H by independent noise channel with their processing path and sigma (see
/// noise_covariance.hpp); H is their rows stacked in that order and y the matching torques.
/// crb_std = sqrt(diag(lsNoiseCovariance(channels))): the bound the sweep and reproduce report
/// for the same processing.
IdentifiabilityReport analyzeIdentifiability(const std::vector<NoiseChannel>& channels, const Eigen::VectorXd& y,
                                             const Eigen::VectorXd& reference = Eigen::VectorXd());

}  // namespace exoid::ident
