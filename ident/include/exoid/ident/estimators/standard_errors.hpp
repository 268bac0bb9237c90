#pragma once
// Standard errors of a least-squares estimate from its own residuals, for logs whose noise level
// nobody gave: the covariance a real robot's fit has, model error included.
//
// The rows an estimator fits are filtered and decimated, and what the model leaves out is slow,
// so the residuals of one channel (one joint's equation of one record, in time order) are
// correlated. The heteroskedasticity- and autocorrelation-consistent estimator of Newey and West
// (1987) keeps that correlation:
//   C = (H^T H)^-1 S (H^T H)^-1,
//   S = sum over channels, sum over |l| <= L of (1 - |l| / (L + 1)) sum_t h_t r_t r_{t+l} h_{t+l}^T
// (Bartlett weights keep S positive semi-definite). With uncorrelated, equal-variance residuals
// it is the textbook sigma^2 (H^T H)^-1 to sampling error.
//
// Its automatic lag is a few rows: a model error as slow as the motion itself (a lumped body, a
// friction law's shape, a band's errors-in-variables bias) stays correlated far longer, and the
// errors miss it (on the shipped real records, fits of one robot scatter 1.4-3.2 times their
// Newey-West errors). The block jackknife sees it: the record cut into contiguous blocks, the fit
// repeated without each, the spread of those fits. The reported error of each parameter is the
// larger of the two.
#include <Eigen/Core>

#include <optional>
#include <vector>

namespace exoid::ident {

/// Newey and West's (1994) automatic lag for Bartlett weights: floor(4 (n / 100)^(2/9)), at
/// least 1. n = rows of the channel.
int neweyWestLags(Eigen::Index n);

/// The rows of one channel of `problem` rows, in time order (indices into H).
using Channel = std::vector<Eigen::Index>;
/// Channels of bothEquations(): hip rows 0, 2, 4, ...; knee rows 1, 3, 5, ...
std::vector<Channel> interleavedChannels(Eigen::Index rows, int equations = 2);

/// The covariance C above of x = argmin ||y - H x|| given residual = y - H x. lags < 0: the
/// automatic lag of the longest channel (in steps). rows_per_step: consecutive rows of a channel
/// that belong to one instant and whose scores h r are summed before the lags (2 for both joint
/// equations of a sample, interleaved: noise in qdd2 and the shank's model error enter both, so
/// their residuals are correlated). Every entry +inf when H^T H is singular. Throws
/// std::invalid_argument on size mismatches, a row index out of range or rows_per_step < 1.
Eigen::MatrixXd residualCovariance(const Eigen::MatrixXd& H, const Eigen::VectorXd& residual,
                                   const std::vector<Channel>& channels, int lags = -1, int rows_per_step = 1);

/// Rows [first, first + rows) of a problem: one contiguous stretch of one record.
struct RowBlock {
  Eigen::Index first = 0, rows = 0;
};
/// Each record (record_rows: rows per record, in order; empty = one record of total_rows) cut into
/// contiguous blocks of whole steps (rows_per_step rows each): `blocks` in all, at least 2 per
/// record. Throws std::invalid_argument when the records do not sum to total_rows.
std::vector<RowBlock> recordBlocks(const std::vector<Eigen::Index>& record_rows, Eigen::Index total_rows, int rows_per_step, int blocks = 10);

/// One block per record: the delete-one-record jackknife's (between-record error: a bias constant
/// within each record, which no block of one record can show).
std::vector<RowBlock> wholeRecords(const std::vector<Eigen::Index>& record_rows, Eigen::Index total_rows);

/// The delete-one-block jackknife covariance of x = argmin ||y - H x||: x refitted without each
/// block g, V = (G - 1) / G sum_g (x_g - mean)(x_g - mean)^T. +inf entries when a fit without some
/// block is singular (the estimate rests on that block alone); NaN with fewer than 2 blocks.
Eigen::MatrixXd blockJackknifeCovariance(const Eigen::MatrixXd& H, const Eigen::VectorXd& y, const std::vector<RowBlock>& blocks);

/// What identify reports of a least-squares estimate: Newey-West's standard errors, the
/// jackknife's (the larger of the within-record blocks' and, with 3 records or more, the
/// delete-one-record one's), the larger of the two per parameter, and the covariance the
/// consistency and usability rules use (Newey-West's correlations, the reported variances).
struct ReportedErrors {
  Eigen::VectorXd newey_west, jackknife, reported;
  Eigen::VectorXd block_jackknife, record_jackknife;  ///< the two jackknives (record: NaN below 3 records)
  std::vector<bool> from_jackknife;  ///< per parameter: reported = jackknife
  Eigen::MatrixXd covariance;
};
/// blocks: recordBlocks(...); records: wholeRecords(...).
ReportedErrors reportedErrors(const Eigen::MatrixXd& H, const Eigen::VectorXd& y, const Eigen::VectorXd& x, const std::vector<Channel>& channels,
                              int rows_per_step, const std::vector<RowBlock>& blocks, const std::vector<RowBlock>& records);

/// reportedErrors' rule on covariances made elsewhere (a segmental fit's, stage by stage): the
/// jackknife's variance is the larger of the blocks' and the records' (when given), each
/// parameter's reported error the larger of it and Newey-West's.
ReportedErrors combineReportedErrors(const Eigen::MatrixXd& newey_west, const Eigen::MatrixXd& block_jackknife,
                                     const std::optional<Eigen::MatrixXd>& record_jackknife);

}  // namespace exoid::ident
