#pragma once
// Recursive least squares with forgetting (paper Eq. 6, with its typos fixed: the identity is
// p x p, and the gain uses lambda directly) and the "fluctuation range" that becomes PSO's box.
#include "exoid/ident/estimators/box.hpp"
#include "exoid/ident/estimators/summary.hpp"

#include <Eigen/Core>

namespace exoid::ident {

struct RlsOptions {
  /// lambda in P = (I - K h^T) P / lambda. Range (0, 1]; 1 = no forgetting (converges to LS).
  double forgetting = 1.0;
  /// P0 = initial_covariance * I. Range > 0. Large = weak prior on the initial estimate.
  double initial_covariance = 1e6;
  /// Keep the estimate after every update (needed for the fluctuation range).
  bool keep_history = true;
  void validate() const;  ///< throws std::invalid_argument naming the field
};

/// Online RLS over p parameters. update() does not allocate (buffers are sized at construction;
/// history storage is reserved with reserveHistory()).
class RecursiveLeastSquares {
 public:
  RecursiveLeastSquares(Eigen::Index p, const RlsOptions& options,
                        const Eigen::VectorXd& initial_estimate = Eigen::VectorXd());
  /// One scalar measurement y = h^T x + e.
  void update(const Eigen::Ref<const Eigen::RowVectorXd>& h, double y);
  /// Two measurements at once (hip and knee rows): y = H x + e, H is 2 x p.
  void update(const Eigen::Ref<const Eigen::Matrix<double, 2, Eigen::Dynamic>>& H,
              const Eigen::Vector2d& y);
  void reserveHistory(Eigen::Index updates);

  const Eigen::VectorXd& estimate() const { return x_; }
  const Eigen::MatrixXd& covariance() const { return P_; }
  Eigen::Index updates() const { return count_; }
  /// p x updates(): column k is the estimate after update k (empty without keep_history).
  Eigen::Ref<const Eigen::MatrixXd> history() const { return history_.leftCols(stored_); }

 private:
  void correct(const Eigen::Ref<const Eigen::RowVectorXd>& h, double y, double lambda);
  void record();
  RlsOptions options_;
  Eigen::VectorXd x_;
  Eigen::MatrixXd P_;
  Eigen::VectorXd Ph_;                         // P h (scalar update)
  Eigen::MatrixXd history_;
  Eigen::Index stored_ = 0;
  Eigen::Index count_ = 0;
};

/// Runs RLS over the rows of H (one scalar update per row) in order.
struct RlsResult {
  Eigen::VectorXd x;        ///< final estimate
  Eigen::MatrixXd history;  ///< p x rows, if kept
  Summary summary;
};
RlsResult runRls(const Eigen::MatrixXd& H, const Eigen::VectorXd& y, const RlsOptions& options = {});

struct FluctuationOptions {
  /// Fraction of the updates discarded at the start (the transient from P0): the range is the
  /// min/max of the estimate over the rest. Range [0, 1). Default 0.1 (1 s of a 10 s record).
  double burn_in_fraction = 0.1;
  /// Each side widened by margin_fraction * (max - min). Range >= 0. Default 0.
  double margin_fraction = 0.0;
  /// A parameter whose range is narrower than this is widened to it (absolute, centred), so the
  /// box stays a box. Range > 0. Default 1e-6.
  double min_width = 1e-6;
  void validate() const;
};

/// The paper's "fluctuation range": per-parameter min/max of the RLS estimate history.
Box fluctuationRange(const Eigen::Ref<const Eigen::MatrixXd>& history,
                     const FluctuationOptions& options = {});

}  // namespace exoid::ident
