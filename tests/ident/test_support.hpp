#pragma once
// Test-only ground truth: an independent 2-link dynamics (d'Alembert on COM accelerations, not
// the Lagrange regressor) and the paper's trajectories with analytic derivatives.
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/leg/params.hpp"
#include "exoid/ident/leg/regressor.hpp"
#include "exoid/ident/signals/preprocess.hpp"
#include "exoid/ident/signals/processing.hpp"

#include <Eigen/Core>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>

namespace exoid::test {

/// The APAL leg's constants (Lt 0.45 m, g 9.81 m/s^2), as most ident tests use them.
inline const ident::LegConstants kLeg{0.45, 9.81};

// Link direction and its perpendicular in the sagittal (x anterior, z up) plane for a link at
// absolute angle th (0 = hanging down, + = distal end moves posterior).
inline Eigen::Vector2d along(double th) { return {-std::sin(th), -std::cos(th)}; }
inline Eigen::Vector2d across(double th) { return {-std::cos(th), std::sin(th)}; }

/// Joint torques of the leg by d'Alembert's principle: tau_j = sum_i m_i a_i . dp_i/dq_j
/// + I_i alpha_i dth_i/dq_j + m_i g dz_i/dq_j + friction.
inline Eigen::Vector2d inverseDynamics(const ident::LegPhysical& leg, double g, const Eigen::Vector2d& q,
                                       const Eigen::Vector2d& qd, const Eigen::Vector2d& qdd) {
  const double th1 = q[0], th2 = q[0] + q[1];
  const double w1 = qd[0], w2 = qd[0] + qd[1];
  const double al1 = qdd[0], al2 = qdd[0] + qdd[1];
  const auto& t = leg.thigh;
  const auto& s = leg.shank;
  // COM offsets from their own joint, as rotating vectors r(th) = a along + h across;
  // r'(th) = a across - h along, r'' = -r.
  const Eigen::Vector2d r1 = t.com_along_m * along(th1) + t.com_offset_m * across(th1);
  const Eigen::Vector2d r1d = t.com_along_m * across(th1) - t.com_offset_m * along(th1);
  const Eigen::Vector2d k = t.length_m * along(th1);  // hip -> knee
  const Eigen::Vector2d kd = t.length_m * across(th1);
  const Eigen::Vector2d r2 = s.com_along_m * along(th2) + s.com_offset_m * across(th2);
  const Eigen::Vector2d r2d = s.com_along_m * across(th2) - s.com_offset_m * along(th2);
  const Eigen::Vector2d a1 = r1d * al1 - r1 * w1 * w1;
  const Eigen::Vector2d a2 = kd * al1 - k * w1 * w1 + r2d * al2 - r2 * w2 * w2;
  // dp1/dq = [r1d, 0]; dp2/dq = [kd + r2d, r2d]; dth1/dq = [1, 0]; dth2/dq = [1, 1].
  Eigen::Vector2d tau;
  tau[0] = t.mass_kg * a1.dot(r1d) + s.mass_kg * a2.dot(kd + r2d) + t.inertia_com_kgm2 * al1 +
           s.inertia_com_kgm2 * al2 + g * (t.mass_kg * r1d[1] + s.mass_kg * (kd[1] + r2d[1]));
  tau[1] = s.mass_kg * a2.dot(r2d) + s.inertia_com_kgm2 * al2 + g * s.mass_kg * r2d[1];
  tau[0] += leg.fc_hip_Nm * ident::sgn(qd[0]) + leg.fv_hip_Nms * qd[0];
  tau[1] += leg.fc_knee_Nm * ident::sgn(qd[1]) + leg.fv_knee_Nms * qd[1];
  return tau;
}

/// Paper Table 1 trajectory `id` (1-4) in rad at time t: q, qd, qdd.
inline void paperTrajectory(int id, double t, Eigen::Vector2d& q, Eigen::Vector2d& qd, Eigen::Vector2d& qdd) {
  const double d = M_PI / 180.0, w = 2.0 * M_PI;
  const double s = std::sin(w * t), c = std::cos(w * t);
  // [offset hip, amplitude hip, offset knee, amplitude knee] in degrees: q = off + amp sin(wt).
  static const double table[4][4] = {{-10, 0, 45, -30}, {-10, 0, 60, -30}, {-30, -30, 75, -30}, {-45, -30, 60, 30}};
  const double* r = table[id - 1];
  q = {d * (r[0] + r[1] * s), d * (r[2] + r[3] * s)};
  qd = {d * r[1] * w * c, d * r[3] * w * c};
  qdd = {-d * r[1] * w * w * s, -d * r[3] * w * w * s};
}

/// Exact signals of a paper trajectory, torques from inverseDynamics(), sampled at 1/dt.
inline ident::JointSignals exactRecord(int id, const ident::LegPhysical& leg, double g, double duration_s = 10.0,
                                       double dt_s = 1e-3) {
  const auto n = static_cast<Eigen::Index>(std::llround(duration_s / dt_s));
  ident::JointSignals s;
  s.t_s.resize(n);
  s.q_rad.resize(n, 2);
  s.qd_radps.resize(n, 2);
  s.qdd_radps2.resize(n, 2);
  s.tau_Nm.resize(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * dt_s;
    Eigen::Vector2d q, qd, qdd;
    paperTrajectory(id, t, q, qd, qdd);
    s.t_s[i] = t;
    s.q_rad.row(i) = q;
    s.qd_radps.row(i) = qd;
    s.qdd_radps2.row(i) = qdd;
    s.tau_Nm.row(i) = inverseDynamics(leg, g, q, qd, qdd);
  }
  return s;
}

/// A dataset of a two-frequency motion of both joints (0.5 + 1.3 Hz hip, 0.7 + 1.9 Hz knee; or of the
/// knee alone with the hip held at -0.4 rad), sampled at 1 kHz, with exact torques from
/// inverseDynamics() and, when with_derivatives, the exact qd/qdd columns. No sample lies on a
/// velocity reversal (|qd| >= 2.9e-4 rad/s over 10 s), where sgn(qd) would be undetermined.
inline ident::Dataset multisineRecord(double duration_s, bool hip_moves = true, bool with_derivatives = true,
                                      double g = 9.81) {
  const auto n = static_cast<Eigen::Index>(std::llround(duration_s * 1000.0));
  ident::Dataset d;
  d.t_s.resize(n);
  d.q_rad.resize(n, 2);
  d.tau_Nm.resize(n, 2);
  Eigen::MatrixX2d qd(n, 2), qdd(n, 2);
  const double w[4] = {2 * M_PI * 0.5, 2 * M_PI * 1.3, 2 * M_PI * 0.7, 2 * M_PI * 1.9};
  const double a[4] = {hip_moves ? 0.4 : 0.0, hip_moves ? 0.15 : 0.0, 0.5, 0.1};
  const double phase[4] = {0.3, 0.0, 1.0, 0.0};
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = 1e-3 * static_cast<double>(i);
    Eigen::Vector2d q(-0.4, 0.9), v(0, 0), acc(0, 0);
    for (int k = 0; k < 4; ++k) {
      const int j = k / 2;
      const double ph = w[k] * t + phase[k];
      q[j] += a[k] * std::sin(ph);
      v[j] += a[k] * w[k] * std::cos(ph);
      acc[j] -= a[k] * w[k] * w[k] * std::sin(ph);
    }
    d.t_s[i] = t;
    d.q_rad.row(i) = q;
    qd.row(i) = v;
    qdd.row(i) = acc;
    d.tau_Nm.row(i) = inverseDynamics(ident::defaultLeg(), g, q, v, acc);
  }
  if (with_derivatives) {
    d.qd_radps = qd;
    d.qdd_radps2 = qdd;
  }
  return d;
}

/// Expects `call` to throw std::invalid_argument whose message contains `text`.
// The iv-band tests' fixed band: parallel processing at 10 Hz, five-point differences after a 50 Hz
// pre-filter.
/// A linear problem y = H x.
struct LinearProblem {
  Eigen::MatrixXd H;
  Eigen::VectorXd y;
};
/// The segmental strategy's knee stage on signals as they are (the paper's stage 1): the knee
/// equation's columns Mxs .. fv2 and its torque.
inline LinearProblem kneeProblem(const ident::JointSignals& s, const ident::LegConstants& c = kLeg) {
  const ident::RecordRows r = ident::recordRows(ident::twoLinkLeg(c), s);
  return {r.jointW(1).middleCols(ident::kShankFirst, ident::kGroupSize), r.jointY(1)};
}

inline ident::SignalOptions tenHertzParallel() {
  ident::SignalOptions o;
  o.processing = ident::Processing::kParallel;
  o.differentiation = ident::Differentiation::kCentral4;
  o.cutoff_hz = 10.0;
  o.derivative_cutoff_hz = 50.0;
  return o;
}

inline void expectInvalidArgumentMentioning(const std::function<void()>& call, const std::string& text) {
  try {
    call();
    ADD_FAILURE() << "expected std::invalid_argument mentioning '" << text << "'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos)
        << "message '" << e.what() << "' does not mention '" << text << "'";
  }
}

}  // namespace exoid::test
