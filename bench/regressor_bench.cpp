// The generic chain regressor (recursive Newton-Euler in regressor form, any serial chain) against
// the hand-written 2-link one, on the APAL leg: rows per second over 100,000 random states, and the
// generic one on a 3-DOF and a 6-DOF chain. The bar: generic >= 1/3 of the hand-written
// rate on the same leg (the ratio is printed by the HandWritten/Generic pair in one run).
//
//   build/bench/regressor_bench --benchmark_counters_tabular=true
#include "exoid/core/random.hpp"
#include "exoid/ident/model/newton_euler.hpp"
#include "exoid/ident/leg/regressor.hpp"

#include <benchmark/benchmark.h>

#include <vector>

namespace {

using namespace exoid::ident;

constexpr int kStates = 100000;

ChainModel sagittalChain(int dof) {
  ChainModel m;
  m.name = "sagittal";
  for (int i = 0; i < dof; ++i) {
    ChainJoint j;
    j.name = "j" + std::to_string(i);
    j.link = "l" + std::to_string(i);
    j.axis = Eigen::Vector3d::UnitY();
    if (i > 0) j.parent_p_joint_m = Eigen::Vector3d(0.0, 0.0, -0.45);
    m.joints.push_back(j);
  }
  return m;
}

Eigen::MatrixXd randomStates(int dof, std::uint64_t seed) {
  exoid::core::Rng rng(seed);
  Eigen::MatrixXd s(3 * dof, kStates);
  for (Eigen::Index k = 0; k < s.size(); ++k) s.data()[k] = rng.uniform(-2.0, 2.0);
  return s;
}

void HandWritten(benchmark::State& state) {
  const Eigen::MatrixXd s = randomStates(2, 1);
  const LegConstants c{0.45, 9.81};
  RegressorRow hip, knee;
  for (auto _ : state) {
    for (int k = 0; k < kStates; ++k) {
      regressorRows(c, s.col(k).segment<2>(0), s.col(k).segment<2>(2), s.col(k).segment<2>(4), hip, knee);
      benchmark::DoNotOptimize(hip.data());
      benchmark::DoNotOptimize(knee.data());
    }
  }
  state.counters["rows_per_s"] = benchmark::Counter(2.0 * kStates, benchmark::Counter::kIsIterationInvariantRate);
}

void Generic(benchmark::State& state) {
  const int dof = static_cast<int>(state.range(0));
  const ChainModel model = sagittalChain(dof);
  const Eigen::MatrixXd s = randomStates(dof, 1);
  ChainRegressorWorkspace work;
  Eigen::MatrixXd Y(dof, model.standardParameterCount());
  const ChainBaseMotion still = ChainBaseMotion::still(model);
  for (auto _ : state) {
    for (int k = 0; k < kStates; ++k) {
      chainRegressorInto(model, s.col(k).segment(0, dof), s.col(k).segment(dof, dof), s.col(k).segment(2 * dof, dof), still, work, Y);
      benchmark::DoNotOptimize(Y.data());
    }
  }
  state.counters["rows_per_s"] = benchmark::Counter(static_cast<double>(dof) * kStates, benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK(HandWritten)->Unit(benchmark::kMillisecond);
BENCHMARK(Generic)->Arg(2)->Arg(3)->Arg(6)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
