#pragma once
// The paper's identification cost over a linear model: sum_i |b_i - a_i^T x| (L1, the paper's)
// or sum_i (b_i - a_i^T x)^2 (L2), evaluated for a whole swarm in one pass over the data.
#include <Eigen/Core>

#include <string>
#include <vector>

namespace exoid::ident {

enum class CostNorm { kL1, kL2 };
const char* toString(CostNorm n);

/// The swarm kernel's instruction set. One portable binary carries all of them and runs the
/// widest the CPU has (kAuto); every one gives the same bits (tested), only the speed differs.
enum class CostKernel { kAuto, kGeneric, kAvx2, kAvx512 };
const char* toString(CostKernel k);
/// "auto", "generic", "avx2" or "avx512"; throws std::invalid_argument naming the choices.
CostKernel parseCostKernel(const std::string& name);
bool costKernelSupported(CostKernel k);
/// The kernels this CPU can run, narrowest first (generic always).
std::vector<CostKernel> supportedCostKernels();
/// The process default: the widest supported, or the environment variable EXOID_COST_KERNEL
/// (auto|generic|avx2|avx512; throws std::runtime_error if the CPU cannot run the one named).
CostKernel defaultCostKernel();

class LinearResidualCost {
 public:
  /// A is N x p (rows are regressor rows), b has N entries. Throws std::invalid_argument on
  /// size mismatch, empty or non-finite data.
  LinearResidualCost(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, CostNorm norm = CostNorm::kL1);

  Eigen::Index dim() const { return A_.cols(); }
  Eigen::Index rows() const { return A_.rows(); }
  CostNorm norm() const { return norm_; }
  /// The kernel evaluate() runs (defaultCostKernel() unless useKernel chose another).
  CostKernel kernel() const { return kernel_; }
  /// Runs evaluate() on kernel k (kAuto: the default). Throws std::invalid_argument if the CPU
  /// cannot run it.
  void useKernel(CostKernel k);

  /// Cost of one parameter vector.
  double operator()(const Eigen::Ref<const Eigen::VectorXd>& x) const;
  /// Costs of all columns of `particles` (p x S) into costs (S). One fused pass: rows are walked
  /// once per block of 8 particles, residuals are never stored (memory-bound otherwise). Up to
  /// 10 parameters; more fall back to one particle at a time.
  void evaluate(const Eigen::Ref<const Eigen::MatrixXd>& particles, Eigen::Ref<Eigen::VectorXd> costs) const;

  /// Floating-point operations of one evaluate() call for S particles (for GFLOP/s reports):
  /// per row and particle p multiply-adds, one subtraction, one abs/square and one add.
  double flops(Eigen::Index particles) const;

 private:
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> A_;
  Eigen::VectorXd b_;
  CostNorm norm_;
  CostKernel kernel_;
};

}  // namespace exoid::ident
