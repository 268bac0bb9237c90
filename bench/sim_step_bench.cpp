// The simulation loop (controller, sensors, checks, recording) against bare mj_step on the same
// model and the same number of steps: 10 s at 1 kHz of paper trajectory 3.
// Argument: vibration level (0 = welded pedestal, 1 = compliant mount).
// Target (issue 8): the loop (controller, actuators, sensors, IMU, checks, recording) within 5 % of
// bare stepping; the feedforward plan is computed before the loop (BM_SimulateTotal includes it).
#include "exoid/sim/four_bar.hpp"
#include "exoid/sim/model.hpp"
#include "exoid/sim/simulate.hpp"

#include <benchmark/benchmark.h>

namespace {

using namespace exoid::sim;

SimConfig config(double level) {
  SimConfig c;
  c.trajectory = 3;
  c.duration_s = 10.0;
  c.variant.vibration_level = level;
  c.sensors.noise_q_deg = 0.01;
  c.sensors.quantisation_deg = 0.001;
  c.sensors.noise_tau_Nm = 0.5;
  c.seed = 7;
  // The ramp is recorded rather than run as an unrecorded pre-roll, so the loop makes exactly the
  // n = duration / dt steps the bare loop replays (with a pre-roll it would make 11000 for 10000
  // counted: a 10 % overhead that is only a miscount).
  c.record_after_ramp = false;
  return c;
}

// Bare stepping: same model variant and initial state; the motor torques of a simulated run are
// replayed open-loop so the motion (and the constraint work) is the same.
void BM_BareMjStep(benchmark::State& state) {
  const SimConfig c = config(static_cast<double>(state.range(0)));
  const SimResult ref = simulate(c);
  const Eigen::VectorXd tau_hip = ref.table.col("tau_hip_true");
  const Eigen::VectorXd tau_knee = ref.table.col("tau_knee_true");
  // The simulator's Coulomb friction, replayed open-loop too (same applied forces, same motion).
  const Eigen::VectorXd qd_hip = ref.table.col("qd_hip_true"), qd_knee = ref.table.col("qd_knee_true");
  LegModel leg = loadLeg(c.model_path, c.variant);
  mjModel* m = leg.model.get();
  m->opt.timestep = c.dt_s;
  const FourBar fb(m, leg.idx);
  DataPtr d = makeData(m);
  const Trajectory traj(c.trajectorySpec(), c.ramp_s);
  const JointReference r0 = traj.at(0.0);
  const Eigen::Index n = tau_hip.size();
  // The simulator pre-loads the mount springs so the pedestal starts in static equilibrium: the
  // same here, or the bare loop would start with the pedestal sagging (another motion).
  setLegState(m, d.get(), leg.idx, fb, {r0.q[0], r0.q[1]}, {0.0, 0.0});
  if (!leg.welded) {
    mj_forward(m, d.get());
    for (int k = 0; k < 3; ++k) {
      m->qpos_spring[leg.idx.mount_qadr[k]] = d->qfrc_bias[leg.idx.mount_vadr[k]] / m->jnt_stiffness[leg.idx.mount_jnt[k]];
    }
  }
  for (auto _ : state) {
    mj_resetData(m, d.get());
    setLegState(m, d.get(), leg.idx, fb, {r0.q[0], r0.q[1]}, {0.0, 0.0});
    for (Eigen::Index k = 0; k < n; ++k) {
      d->ctrl[leg.idx.act[0]] = tau_hip[k];
      d->ctrl[leg.idx.act[1]] = tau_knee[k];
      d->qfrc_applied[leg.idx.vadr[0]] = -leg.coulomb.torque(0, qd_hip[k]);
      d->qfrc_applied[leg.idx.vadr[1]] = -leg.coulomb.torque(1, qd_knee[k]);
      mj_step(m, d.get());
    }
    benchmark::DoNotOptimize(d->qpos[0]);
  }
  state.counters["steps"] = static_cast<double>(n);
  state.counters["per_step"] = benchmark::Counter(
      static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// The simulator's stepping loop (Simulator::run): reference, encoder, PID, Coulomb, mj_step,
// warning/finite/loop checks, torque sensor, recording. Setup (model loading) is excluded.
void BM_SimulationLoop(benchmark::State& state) {
  const SimConfig c = config(static_cast<double>(state.range(0)));
  const auto n = static_cast<double>(std::llround(c.duration_s / c.dt_s));
  for (auto _ : state) {
    state.PauseTiming();
    Simulator sim(c);
    state.ResumeTiming();
    sim.run();
    state.PauseTiming();
    benchmark::DoNotOptimize(&sim);
    // destructor outside the timed region
    state.ResumeTiming();
  }
  state.counters["steps"] = n;
  state.counters["per_step"] = benchmark::Counter(
      n, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// Everything simulate() does: loading, loop, ideal torques, truths, statistics, table.
void BM_SimulateTotal(benchmark::State& state) {
  const SimConfig c = config(static_cast<double>(state.range(0)));
  for (auto _ : state) {
    SimResult r = simulate(c);
    benchmark::DoNotOptimize(r.table.values.data());
  }
}

}  // namespace

BENCHMARK(BM_BareMjStep)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimulationLoop)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimulateTotal)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
