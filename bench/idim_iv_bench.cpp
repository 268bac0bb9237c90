// IDIM-IV's cost on a 10 s, 1 kHz closed-loop record pair (the segmental strategy: a knee record
// with the hip locked, a record where both joints swing), against its parts: one closed-loop
// simulation of the model, one parallel processing of a record, and LS on the same rows (the
// iteration's starting point). The records are the tests' closed-loop multisine
// (tests/support/closed_loop_multisine.hpp: ident's own closed-loop simulation, so the bench needs
// no MuJoCo) with encoder and torque noise (std 8.7e-5 rad = 0.005 deg and 0.5 N m).
//
//   build/bench/idim_iv_bench --benchmark_counters_tabular=true
#include "exoid/ident/estimators/idim_iv.hpp"

#include "../tests/support/closed_loop_multisine.hpp"

#include <benchmark/benchmark.h>

#include <stdexcept>
#include <string>

namespace {

using namespace exoid::ident;

const LegConstants kC = exoid::test::kMultisineConstants;

SignalOptions parallel() {
  SignalOptions o;
  o.processing = Processing::kParallel;
  return o;
}

ClosedLoopRecord makeRecord(bool hip_locked, std::uint64_t seed) {
  namespace test = exoid::test;
  const test::ClosedLoopMultisine m = test::closedLoopMultisine(10001, test::rigController(hip_locked));
  if (!m.run.ok) throw std::runtime_error("closed-loop multisine: " + m.run.message);
  return test::closedLoopRecordOf(m, test::measuredMultisine(m, {8.7e-5, 0.5, seed}, false));
}

struct Records {
  ClosedLoopRecord knee = makeRecord(true, 1), both = makeRecord(false, 2);
};
const Records& records() {
  static const Records r;
  return r;
}

void BM_IdimIvSegmental(benchmark::State& state) {
  const Records& r = records();
  long iterations = 0;
  for (auto _ : state) {
    const SegmentalResult s = identifySegmentalIdimIv(twoLinkLeg(kC), {{1, r.knee}, {0, r.both}});
    iterations = s.stages[0].estimate.summary.iterations + s.stages[1].estimate.summary.iterations;
    benchmark::DoNotOptimize(s.theta.data());
  }
  state.counters["iv_iterations"] = static_cast<double>(iterations);
}
BENCHMARK(BM_IdimIvSegmental)->Unit(benchmark::kMillisecond);

void BM_ClosedLoopSimulation(benchmark::State& state) {
  const Records& r = records();
  const Eigen::VectorXd x = toParamVector(defaultLeg());
  const Robot leg = twoLinkLeg(kC);
  for (auto _ : state) benchmark::DoNotOptimize(simulateClosedLoop(leg, x, r.both.controller, r.both.reference).ok);
}
BENCHMARK(BM_ClosedLoopSimulation)->Unit(benchmark::kMillisecond);

void BM_ParallelProcessing(benchmark::State& state) {
  const Records& r = records();
  const Robot leg = twoLinkLeg(kC);
  const ClosedLoopRun run = simulateClosedLoop(leg, toParamVector(defaultLeg()), r.both.controller, r.both.reference);
  for (auto _ : state) benchmark::DoNotOptimize(parallelProcess(run.states, leg, parallel(), 1000.0).W.data());
}
BENCHMARK(BM_ParallelProcessing)->Unit(benchmark::kMillisecond);

void BM_LeastSquaresSegmental(benchmark::State& state) {
  const Records& r = records();
  MethodOptions o;
  o.report_optimality_gap = false;
  for (auto _ : state) {
    benchmark::DoNotOptimize(identifySegmental(twoLinkLeg(kC), {{1, r.knee.measured}, {0, r.both.measured}}, Method::kLs, o).theta.data());
  }
}
BENCHMARK(BM_LeastSquaresSegmental)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
