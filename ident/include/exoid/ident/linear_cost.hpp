#pragma once
// The paper's identification cost over a linear model: sum_i |b_i - a_i^T x| (L1, the paper's)
// or sum_i (b_i - a_i^T x)^2 (L2), evaluated for a whole swarm in one pass over the data.
#include <Eigen/Core>

namespace exoid::ident {

enum class CostNorm { kL1, kL2 };
const char* toString(CostNorm n);

class LinearResidualCost {
 public:
  /// A is N x p (rows are regressor rows), b has N entries. Throws std::invalid_argument on
  /// size mismatch, empty or non-finite data.
  LinearResidualCost(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, CostNorm norm = CostNorm::kL1);

  Eigen::Index dim() const { return A_.cols(); }
  Eigen::Index rows() const { return A_.rows(); }
  CostNorm norm() const { return norm_; }

  /// Cost of one parameter vector.
  double operator()(const Eigen::Ref<const Eigen::VectorXd>& x) const;
  /// Costs of all columns of `particles` (p x S) into costs (S). One fused pass: rows are walked
  /// once per block of 8 particles, residuals are never stored (memory-bound otherwise).
  void evaluate(const Eigen::Ref<const Eigen::MatrixXd>& particles, Eigen::Ref<Eigen::VectorXd> costs) const;

  /// Floating-point operations of one evaluate() call for S particles (for GFLOP/s reports):
  /// per row and particle p multiply-adds, one subtraction, one abs/square and one add.
  double flops(Eigen::Index particles) const;

 private:
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> A_;
  Eigen::VectorXd b_;
  CostNorm norm_;
};

}  // namespace exoid::ident
