// IDIM-IV's cost on a 10 s, 1 kHz closed-loop record pair (the segmental strategy: a knee record
// with the hip locked, a record where both joints swing), against its parts: one closed-loop
// simulation of the model, one parallel processing of a record, and LS on the same rows (the
// iteration's starting point). Records come from ident's own closed-loop simulation with encoder
// and torque noise (uniform, std 8.7e-5 rad = 0.005 deg and 0.5 N m), so the bench needs no MuJoCo.
//
//   build/bench/idim_iv_bench --benchmark_counters_tabular=true
#include "exoid/ident/estimators/idim_iv.hpp"
#include "exoid/core/random.hpp"

#include <benchmark/benchmark.h>

namespace {

using namespace exoid::ident;

const LegConstants kC{0.45, 9.81};

SignalOptions parallel() {
  SignalOptions o;
  o.processing = Processing::kParallel;
  return o;
}

ClosedLoopRecord makeRecord(bool hip_locked, std::uint64_t seed) {
  const Eigen::Index n = 10001;
  Eigen::VectorXd t(n);
  Eigen::MatrixX2d q_ref(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double s = 1e-3 * static_cast<double>(i);
    t[i] = s;
    q_ref.row(i) << (hip_locked ? -0.17 : -0.52 + 0.52 * std::sin(2 * M_PI * s)), 1.31 - 0.52 * std::sin(2 * M_PI * s);
  }
  ClosedLoopRecord r;
  r.reference = referenceFromAngles(t, q_ref);
  r.controller.pid.kp_Nm_per_rad << 2200.0, 380.0;
  r.controller.pid.ki_Nm_per_rad_s << 6900.0, 1200.0;
  r.controller.pid.kd_Nms_per_rad << 176.0, 30.0;
  r.controller.pid.derivative_cutoff_hz = 100.0;
  r.controller.locked = {hip_locked, false};
  const ClosedLoopRun run = simulateClosedLoop(toParamVector(defaultLeg()), kC, r.controller, r.reference);
  exoid::core::Rng rng(seed);
  Dataset d;
  d.t_s = t;
  d.q_rad = run.states.q_rad + Eigen::MatrixX2d::NullaryExpr(n, 2, [&](Eigen::Index, Eigen::Index) { return rng.uniform(-1.5e-4, 1.5e-4); });
  d.tau_Nm = run.states.tau_Nm + Eigen::MatrixX2d::NullaryExpr(n, 2, [&](Eigen::Index, Eigen::Index) { return rng.uniform(-0.87, 0.87); });
  r.measured = processRecord(d, kC, parallel());
  return r;
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
    const SegmentalResult s = identifySegmentalIv(r.knee, r.both, kC, parallel(), {});
    iterations = s.knee.summary.iterations + s.hip.summary.iterations;
    benchmark::DoNotOptimize(s.x.data());
  }
  state.counters["iv_iterations"] = static_cast<double>(iterations);
}
BENCHMARK(BM_IdimIvSegmental)->Unit(benchmark::kMillisecond);

void BM_ClosedLoopSimulation(benchmark::State& state) {
  const Records& r = records();
  const ParamVector x = toParamVector(defaultLeg());
  for (auto _ : state) benchmark::DoNotOptimize(simulateClosedLoop(x, kC, r.both.controller, r.both.reference).ok);
}
BENCHMARK(BM_ClosedLoopSimulation)->Unit(benchmark::kMillisecond);

void BM_ParallelProcessing(benchmark::State& state) {
  const Records& r = records();
  const ClosedLoopRun run = simulateClosedLoop(toParamVector(defaultLeg()), kC, r.both.controller, r.both.reference);
  for (auto _ : state) benchmark::DoNotOptimize(parallelProcess(run.states, kC, parallel(), 1000.0).hip.data());
}
BENCHMARK(BM_ParallelProcessing)->Unit(benchmark::kMillisecond);

void BM_LeastSquaresSegmental(benchmark::State& state) {
  const Records& r = records();
  MethodOptions o;
  o.report_optimality_gap = false;
  for (auto _ : state) {
    benchmark::DoNotOptimize(identifySegmental(Method::kLs, r.knee.measured, r.both.measured, o).x.data());
  }
}
BENCHMARK(BM_LeastSquaresSegmental)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
