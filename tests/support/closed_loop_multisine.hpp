#pragma once
// The closed-loop multisine record, in one place for the tests and the benchmarks: the default leg
// (ident's own closed-loop model: no MuJoCo, so ident's tests may use it) tracking a two-frequency
// reference per joint under the rig's PID and the model's feedforward, sampled at 1 kHz, with
// optional white encoder and torque noise. Header-only and free of gtest: tests/ includes it as
// "../support/closed_loop_multisine.hpp", bench/ as "../tests/support/closed_loop_multisine.hpp";
// it needs exoid::ident only.
#include "exoid/ident/estimators/idim_iv.hpp"
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/leg/params.hpp"
#include "exoid/ident/model/closed_loop.hpp"
#include "exoid/ident/model/robot.hpp"

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <random>

namespace exoid::test {

/// Thigh length and gravity of the record (the default leg's rig).
inline const ident::LegConstants kMultisineConstants{0.45, 9.81};
/// Where the knee-only record holds the hip, rad.
inline constexpr double kMultisineHipHold_rad = -0.3;

/// The reference, n samples from t = 0 at 1 kHz: hip -0.5 + 0.4 sin(2 pi 0.5 t) + 0.1 sin(2 pi 1.3 t)
/// (held at kMultisineHipHold_rad when hip_locked), knee 1.0 + 0.5 sin(2 pi 0.7 t + 0.4) +
/// 0.1 sin(2 pi 1.9 t), rad; its derivatives by ident::referenceFromAngles.
inline ident::Reference multisineReference(Eigen::Index n, bool hip_locked = false) {
  Eigen::VectorXd t(n);
  Eigen::MatrixX2d q_ref(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double s = 1e-3 * static_cast<double>(i);
    q_ref.row(i) << (hip_locked ? kMultisineHipHold_rad : -0.5 + 0.4 * std::sin(2 * M_PI * 0.5 * s) + 0.1 * std::sin(2 * M_PI * 1.3 * s)),
        1.0 + 0.5 * std::sin(2 * M_PI * 0.7 * s + 0.4) + 0.1 * std::sin(2 * M_PI * 1.9 * s);
    t[i] = s;
  }
  return ident::Reference::fromAngles(t, q_ref);
}

/// The rig's tracking controller: PID kp 2200 / 380 N m/rad, ki 6900 / 1200 N m/(rad s), kd 176 /
/// 30 N m s/rad (hip / knee), derivative low-passed at 100 Hz, the model's feedforward; the hip
/// locked for the knee-only record.
inline ident::Controller rigController(bool hip_locked) {
  ident::Controller ctl;
  ctl.kp_Nm_per_rad = Eigen::Vector2d(2200.0, 380.0);
  ctl.ki_Nm_per_rad_s = Eigen::Vector2d(6900.0, 1200.0);
  ctl.kd_Nms_per_rad = Eigen::Vector2d(176.0, 30.0);
  ctl.derivative_cutoff_hz = 100.0;
  ctl.locked = {hip_locked, false};
  return ctl;
}

/// The default leg under `controller` along the multisine (the hip held when the controller locks
/// it). `run.ok` says whether the simulation went through (callers assert it).
struct ClosedLoopMultisine {
  ident::Reference reference;
  ident::Controller controller;
  ident::ClosedLoopRun run;
};

inline ClosedLoopMultisine closedLoopMultisine(Eigen::Index n, const ident::Controller& controller) {
  ClosedLoopMultisine m{multisineReference(n, controller.isLocked(0)), controller, {}};
  m.run = ident::simulateClosedLoop(ident::twoLinkLeg(kMultisineConstants), ident::toParamVector(ident::defaultLeg()), controller, m.reference);
  return m;
}

/// White Gaussian noise on the recorded angles and torques (std; 0 = exact), drawn from
/// std::mt19937_64(seed) sample by sample, joint by joint, angle before torque.
struct MultisineNoise {
  double q_rad = 0.0;
  double tau_Nm = 0.0;
  std::uint64_t seed = 1;
};

/// What the rig logs of the run: t, the angles and torques with `noise`, and, when
/// recorded_derivatives, the exact qd and qdd.
inline ident::Dataset measuredMultisine(const ClosedLoopMultisine& m, const MultisineNoise& noise, bool recorded_derivatives) {
  std::mt19937_64 rng(noise.seed);
  std::normal_distribution<double> n01;
  ident::Dataset d;
  d.t_s = m.reference.t_s;
  d.q_rad = m.run.states.q_rad;
  d.tau_Nm = m.run.states.tau_Nm;
  for (Eigen::Index i = 0; i < d.size(); ++i) {
    for (int j = 0; j < 2; ++j) {
      d.q_rad(i, j) += noise.q_rad * n01(rng);
      d.tau_Nm(i, j) += noise.tau_Nm * n01(rng);
    }
  }
  if (recorded_derivatives) {
    d.qd_radps = m.run.states.qd_radps;
    d.qdd_radps2 = m.run.states.qdd_radps2;
  }
  return d;
}

/// IDIM-IV's input: the measured record processed in parallel, with the reference and controller
/// it was recorded under.
inline ident::ClosedLoopRecord closedLoopRecordOf(const ClosedLoopMultisine& m, const ident::Dataset& measured) {
  ident::SignalOptions parallel;
  parallel.processing = ident::Processing::kParallel;
  ident::ClosedLoopRecord r;
  r.reference = m.reference;
  r.controller = m.controller;
  r.signals = parallel;
  r.measured = ident::processRecord(measured, ident::twoLinkLeg(kMultisineConstants), parallel);
  return r;
}

}  // namespace exoid::test
