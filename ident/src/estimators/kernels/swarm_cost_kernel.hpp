#pragma once
// The fused swarm-cost kernel of LinearResidualCost, compiled once per instruction set and picked
// at run time (linear_cost.cpp), so a portable build keeps the speed of a -march=native one and a
// binary never executes an instruction its CPU lacks.
//
// The interface is raw pointers on purpose: these translation units are compiled with ISA flags,
// and any inline function they shared with the rest of the program (Eigen's included) could be
// emitted with those instructions and then picked by the linker for everybody.
#include <cstddef>

namespace exoid::ident::kernels {

struct SwarmCostArgs {
  const double* A;          ///< n x p, row-major
  const double* b;          ///< n
  std::ptrdiff_t n;         ///< rows
  int p;                    ///< parameters, 1..kMaxParams
  bool l1;                  ///< L1 (sum |r|) or L2 (sum r^2)
  const double* particles;  ///< p x S, column-major with leading dimension ld
  std::ptrdiff_t ld;
  std::ptrdiff_t S;
  double* costs;            ///< S
  using Fn = void (*)(const SwarmCostArgs&);
};

constexpr int kMaxParams = 10;

// One per instruction set; each exists in every build (the x86 ones fall back to the generic code
// when the compiler cannot target them), the dispatcher only calls what the CPU supports.
void swarmCostGeneric(const SwarmCostArgs& a);
void swarmCostAvx2(const SwarmCostArgs& a);
void swarmCostAvx512(const SwarmCostArgs& a);

}  // namespace exoid::ident::kernels
