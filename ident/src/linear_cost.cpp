#include "exoid/ident/linear_cost.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace exoid::ident {

const char* toString(CostNorm n) { return n == CostNorm::kL1 ? "L1" : "L2"; }

LinearResidualCost::LinearResidualCost(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, CostNorm norm)
    : A_(A), b_(b), norm_(norm) {
  if (A.rows() != b.size() || A.rows() == 0 || A.cols() == 0) {
    throw std::invalid_argument("cost: regressor is " + std::to_string(A.rows()) + " x " +
                                std::to_string(A.cols()) + " but the torque vector has " +
                                std::to_string(b.size()) + " entries");
  }
  if (!A.allFinite() || !b.allFinite()) throw std::invalid_argument("cost: data contain NaN or Inf");
}

double LinearResidualCost::operator()(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  if (x.size() != dim()) {
    throw std::invalid_argument("cost: expected " + std::to_string(dim()) + " parameters, got " +
                                std::to_string(x.size()));
  }
  const Eigen::VectorXd r = b_ - A_ * x;
  return norm_ == CostNorm::kL1 ? r.cwiseAbs().sum() : r.squaredNorm();
}

double LinearResidualCost::flops(Eigen::Index particles) const {
  return static_cast<double>(rows()) * static_cast<double>(particles) * (2.0 * static_cast<double>(dim()) + 2.0);
}

namespace {

constexpr int kLanes = 8;  // particles per block: one AVX-512 register, two AVX2 registers

// GCC/Clang vector extensions: the compiler maps these onto the widest registers it has, so the
// kernel neither depends on the auto-vectoriser's mood (it produced 5x slower code for plain
// loops under -DNDEBUG) nor on an instruction set.
using Lanes = double __attribute__((vector_size(kLanes * sizeof(double))));
using LaneBits = long long __attribute__((vector_size(kLanes * sizeof(double))));

inline Lanes broadcast(double v) { return Lanes{} + v; }

// Accumulates the cost of kLanes particles, x[k] holding dimension k of each. Four rows per step
// with separate accumulators so the adds do not serialise on one dependency chain. Kept out of
// line: inlined into evaluateFixed, GCC 12 kept x in memory and ran 3x slower (measured).
template <int P, bool kL1>
[[gnu::noinline]] Lanes blockKernel(const double* A, const double* b, Eigen::Index n, const Lanes (&x)[P]) {
  const LaneBits abs_mask = LaneBits{} + 0x7fffffffffffffffLL;
  auto row = [&](Eigen::Index i) {
    const double* ai = A + i * P;
    Lanes r = broadcast(b[i]);
    for (int k = 0; k < P; ++k) r -= ai[k] * x[k];
    if constexpr (kL1) {
      return reinterpret_cast<Lanes>(reinterpret_cast<LaneBits>(r) & abs_mask);
    } else {
      return r * r;
    }
  };
  Lanes acc0{}, acc1{}, acc2{}, acc3{};
  Eigen::Index i = 0;
  for (; i + 4 <= n; i += 4) {
    acc0 += row(i);
    acc1 += row(i + 1);
    acc2 += row(i + 2);
    acc3 += row(i + 3);
  }
  for (; i < n; ++i) acc0 += row(i);
  return (acc0 + acc1) + (acc2 + acc3);
}

template <int P>
void evaluateFixed(const double* A, const double* b, Eigen::Index n, CostNorm norm,
                   const Eigen::Ref<const Eigen::MatrixXd>& particles, Eigen::Ref<Eigen::VectorXd> costs) {
  const Eigen::Index S = particles.cols();
  for (Eigen::Index j0 = 0; j0 < S; j0 += kLanes) {
    Lanes x[P];
    const Eigen::Index lanes = std::min<Eigen::Index>(kLanes, S - j0);
    for (int l = 0; l < kLanes; ++l) {
      // Lanes past the swarm repeat its last particle; their costs are discarded.
      const Eigen::Index j = j0 + std::min<Eigen::Index>(l, lanes - 1);
      for (int k = 0; k < P; ++k) x[k][l] = particles(k, j);
    }
    const Lanes out = norm == CostNorm::kL1 ? blockKernel<P, true>(A, b, n, x) : blockKernel<P, false>(A, b, n, x);
    for (Eigen::Index l = 0; l < lanes; ++l) costs[j0 + l] = out[l];
  }
}

}  // namespace

void LinearResidualCost::evaluate(const Eigen::Ref<const Eigen::MatrixXd>& particles,
                                  Eigen::Ref<Eigen::VectorXd> costs) const {
  if (particles.rows() != dim() || costs.size() != particles.cols()) {
    throw std::invalid_argument("cost: particles must be " + std::to_string(dim()) +
                                " x S with S costs, got " + std::to_string(particles.rows()) + " x " +
                                std::to_string(particles.cols()) + " and " + std::to_string(costs.size()));
  }
  const double* A = A_.data();
  const double* b = b_.data();
  const Eigen::Index n = rows();
  switch (dim()) {
    case 1: return evaluateFixed<1>(A, b, n, norm_, particles, costs);
    case 2: return evaluateFixed<2>(A, b, n, norm_, particles, costs);
    case 3: return evaluateFixed<3>(A, b, n, norm_, particles, costs);
    case 4: return evaluateFixed<4>(A, b, n, norm_, particles, costs);
    case 5: return evaluateFixed<5>(A, b, n, norm_, particles, costs);
    case 6: return evaluateFixed<6>(A, b, n, norm_, particles, costs);
    case 7: return evaluateFixed<7>(A, b, n, norm_, particles, costs);
    case 8: return evaluateFixed<8>(A, b, n, norm_, particles, costs);
    case 9: return evaluateFixed<9>(A, b, n, norm_, particles, costs);
    case 10: return evaluateFixed<10>(A, b, n, norm_, particles, costs);
    default:
      for (Eigen::Index j = 0; j < particles.cols(); ++j) costs[j] = (*this)(particles.col(j));
  }
}

}  // namespace exoid::ident
