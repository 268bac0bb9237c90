#include "exoid/ident/estimators/linear_cost.hpp"

#include "exoid/core/format.hpp"

#include "kernels/swarm_cost_kernel.hpp"

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace exoid::ident {

namespace {

bool cpuHas(CostKernel k) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  __builtin_cpu_init();  // needed if the first call comes from a static initialiser
  switch (k) {
    case CostKernel::kAvx512: return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq");
    case CostKernel::kAvx2: return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    default: return true;
  }
#else
  return k == CostKernel::kGeneric || k == CostKernel::kAuto;  // the ISA units hold generic code here
#endif
}

kernels::SwarmCostArgs::Fn kernelFunction(CostKernel k) {
  switch (k) {
    case CostKernel::kAvx512: return kernels::swarmCostAvx512;
    case CostKernel::kAvx2: return kernels::swarmCostAvx2;
    default: return kernels::swarmCostGeneric;
  }
}

std::string supportedKernelList() {
  std::string out;
  for (CostKernel k : supportedCostKernels()) out += (out.empty() ? "" : ", ") + std::string(toString(k));
  return out;
}

// The widest the CPU runs, unless EXOID_COST_KERNEL names one (to measure or compare them).
CostKernel chooseDefaultKernel() {
  if (const char* env = std::getenv("EXOID_COST_KERNEL"); env != nullptr && *env != '\0') {
    const CostKernel k = parseCostKernel(env);
    if (!cpuHas(k)) {
      throw std::runtime_error(std::string("EXOID_COST_KERNEL=") + env + ": this CPU cannot run it (it can run: " +
                               supportedKernelList() + ")");
    }
    if (k != CostKernel::kAuto) return k;
  }
  for (CostKernel k : {CostKernel::kAvx512, CostKernel::kAvx2}) {
    if (cpuHas(k)) return k;
  }
  return CostKernel::kGeneric;
}

}  // namespace

const char* toString(CostKernel k) {
  switch (k) {
    case CostKernel::kAuto: return "auto";
    case CostKernel::kGeneric: return "generic";
    case CostKernel::kAvx2: return "avx2";
    case CostKernel::kAvx512: return "avx512";
  }
  return "?";
}

CostKernel parseCostKernel(const std::string& name) {
  for (CostKernel k : {CostKernel::kAuto, CostKernel::kGeneric, CostKernel::kAvx2, CostKernel::kAvx512}) {
    if (name == toString(k)) return k;
  }
  throw std::invalid_argument("cost kernel '" + name + "': expected auto, generic, avx2 or avx512");
}

bool costKernelSupported(CostKernel k) { return cpuHas(k); }

std::vector<CostKernel> supportedCostKernels() {
  std::vector<CostKernel> out;
  for (CostKernel k : {CostKernel::kGeneric, CostKernel::kAvx2, CostKernel::kAvx512}) {
    if (cpuHas(k)) out.push_back(k);
  }
  return out;
}

CostKernel defaultCostKernel() {
  static const CostKernel k = chooseDefaultKernel();
  return k;
}

const char* toString(CostNorm n) { return n == CostNorm::kL1 ? "L1" : "L2"; }

LinearResidualCost::LinearResidualCost(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, CostNorm norm)
    : A_(A), b_(b), norm_(norm), kernel_(defaultCostKernel()) {
  if (A.rows() != b.size() || A.rows() == 0 || A.cols() == 0) {
    throw std::invalid_argument("cost: regressor is " + core::toText(A.rows()) + " x " +
                                core::toText(A.cols()) + " but the torque vector has " +
                                core::toText(b.size()) + " entries");
  }
  if (!A.allFinite() || !b.allFinite()) throw std::invalid_argument("cost: data contain NaN or Inf");
}

double LinearResidualCost::operator()(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  if (x.size() != dim()) {
    throw std::invalid_argument("cost: expected " + core::toText(dim()) + " parameters, got " +
                                core::toText(x.size()));
  }
  const Eigen::VectorXd r = b_ - A_ * x;
  return norm_ == CostNorm::kL1 ? r.cwiseAbs().sum() : r.squaredNorm();
}

double LinearResidualCost::flops(Eigen::Index particles) const {
  return static_cast<double>(rows()) * static_cast<double>(particles) * (2.0 * static_cast<double>(dim()) + 2.0);
}

void LinearResidualCost::evaluate(const Eigen::Ref<const Eigen::MatrixXd>& particles,
                                  Eigen::Ref<Eigen::VectorXd> costs) const {
  if (particles.rows() != dim() || costs.size() != particles.cols()) {
    throw std::invalid_argument("cost: particles must be " + core::toText(dim()) +
                                " x S with S costs, got " + core::toText(particles.rows()) + " x " +
                                core::toText(particles.cols()) + " and " + core::toText(costs.size()));
  }
  if (dim() > kernels::kMaxParams) {
    for (Eigen::Index j = 0; j < particles.cols(); ++j) costs[j] = (*this)(particles.col(j));
    return;
  }
  const kernels::SwarmCostArgs args{A_.data(), b_.data(), rows(), static_cast<int>(dim()), norm_ == CostNorm::kL1,
                                    particles.data(), particles.outerStride(), particles.cols(), costs.data()};
  kernelFunction(kernel_)(args);
}

void LinearResidualCost::useKernel(CostKernel k) {
  if (!costKernelSupported(k)) {
    throw std::invalid_argument(std::string("cost: this CPU cannot run the ") + toString(k) +
                                " kernel (it can run: " + supportedKernelList() + ")");
  }
  kernel_ = k == CostKernel::kAuto ? defaultCostKernel() : k;
}

}  // namespace exoid::ident
