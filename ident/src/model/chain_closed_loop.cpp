#include "exoid/ident/model/chain_closed_loop.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/model/chain_regressor.hpp"
#include "exoid/ident/signals/signals.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace exoid::ident {

void ChainController::validate(int dof) const {
  const auto check = [&](const Eigen::VectorXd& v, const char* name) {
    if (v.size() != dof) {
      throw std::invalid_argument(std::string("controller: '") + name + "' has " + core::toText(v.size()) + " values, the chain " +
                                  core::toText(dof) + " joints");
    }
    for (Eigen::Index j = 0; j < v.size(); ++j) {
      if (!(std::isfinite(v[j]) && v[j] >= 0.0)) {
        throw std::invalid_argument(std::string("controller: '") + name + "' must be finite and >= 0, got " + core::toText(v[j]));
      }
    }
  };
  check(kp_Nm_per_rad, "kp");
  check(kd_Nms_per_rad, "kd");
  if (!(kp_Nm_per_rad.maxCoeff() > 0.0)) throw std::invalid_argument("controller: every 'kp' is 0: nothing holds the motion on the reference");
  if (!(std::isfinite(actuator_bandwidth_hz) && actuator_bandwidth_hz >= 0.0)) {
    throw std::invalid_argument("controller: 'actuator_bandwidth_hz' must be finite and >= 0, got " + core::toText(actuator_bandwidth_hz));
  }
}

namespace {

// The model's dynamics from its regressor: tau = Y(q, qd, qdd) phi = M(q) qdd + h(q, qd).
class ChainDynamics {
 public:
  ChainDynamics(const ChainModel& model, const BaseParameters& base, const Eigen::VectorXd& beta)
      : model_(model), phi_(Eigen::VectorXd::Zero(model.standardParameterCount())), Y_(model.dof(), model.standardParameterCount()) {
    for (int i = 0; i < base.rank; ++i) phi_[base.independent[static_cast<std::size_t>(i)]] = beta[i];
  }
  Eigen::VectorXd torque(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    chainRegressorInto(model_, q, qd, qdd, ChainBaseMotion::still(model_), work_, Y_);
    return Y_ * phi_;
  }
  Eigen::MatrixXd mass(const Eigen::VectorXd& q) {
    const Eigen::Index n = q.size();
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
    const Eigen::VectorXd g = torque(q, zero, zero);
    Eigen::MatrixXd m(n, n);
    for (Eigen::Index j = 0; j < n; ++j) m.col(j) = torque(q, zero, Eigen::VectorXd::Unit(n, j)) - g;
    return m;
  }

 private:
  const ChainModel& model_;
  Eigen::VectorXd phi_;
  Eigen::MatrixXd Y_;
  ChainRegressorWorkspace work_;
};

std::string at(double t) {
  std::ostringstream ss;
  ss.precision(6);
  ss << " at t = " << t << " s";
  return ss.str();
}

}  // namespace

ClosedLoopRun simulateChainClosedLoop(const ChainModel& model, const BaseParameters& base, const Eigen::VectorXd& beta,
                                      const ChainController& ctl, const ChainReference& ref) {
  model.validate();
  const int dof = model.dof();
  ctl.validate(dof);
  ref.validate();
  if (ref.q_rad.cols() != dof || beta.size() != base.rank) {
    throw std::invalid_argument("chain closed loop: the reference has " + core::toText(ref.q_rad.cols()) + " joints and beta " +
                                core::toText(beta.size()) + " values; the model " + core::toText(dof) + " joints and " +
                                core::toText(base.rank) + " base parameters");
  }
  ChainDynamics dyn(model, base, beta);
  const Eigen::Index n = ref.size();
  const double dt = (ref.t_s[n - 1] - ref.t_s[0]) / static_cast<double>(n - 1);
  ClosedLoopRun run;
  Eigen::VectorXd q = ref.q_rad.row(0).transpose(), qd = ref.qd_radps.row(0).transpose();
  // Substeps for the stiffest loop at the start (omega = max(sqrt(kp / Mjj), kd / Mjj)). The motor's
  // lag needs none: its update, 1 - exp(-2 pi f h), is exact for the command held over a step.
  const Eigen::MatrixXd m0 = dyn.mass(q);
  double omega = 0.0;
  for (int j = 0; j < dof; ++j) {
    if (!(m0(j, j) > 0.0)) {
      run.message = "the model's mass matrix is not positive definite (M" + core::toText(j + 1) + core::toText(j + 1) + " = " +
                    core::toText(m0(j, j)) + at(ref.t_s[0]) + ")";
      return run;
    }
    omega = std::max({omega, std::sqrt(ctl.kp_Nm_per_rad[j] / m0(j, j)), ctl.kd_Nms_per_rad[j] / m0(j, j)});
  }
  // A loop this stiff against the model's inertia (e.g. the gains of a locked joint, tuned to the
  // lock's 1e9 kg m^2) is no rig's: refused rather than integrated for hours.
  constexpr double kMaxSubsteps = 1000.0;
  if (!(omega * dt / 0.05 <= kMaxSubsteps)) {
    run.message = "the controller's loop is too stiff for the model (" + core::toText(omega) + " rad/s: over " +
                  core::toText(static_cast<long>(kMaxSubsteps)) + " substeps per sample; gains of a locked joint?)";
    return run;
  }
  const int substeps = std::max(1, static_cast<int>(std::ceil(omega * dt / 0.05)));
  const double h = dt / substeps;
  const double lag = ctl.actuator_bandwidth_hz > 0.0 ? 1.0 - std::exp(-2.0 * M_PI * ctl.actuator_bandwidth_hz * h) : 1.0;
  JointSignals& s = run.states;
  s.t_s = ref.t_s;
  s.q_rad.resize(n, dof);
  s.qd_radps.resize(n, dof);
  s.qdd_radps2.resize(n, dof);
  s.tau_Nm.resize(n, dof);
  Eigen::VectorXd motor(dof), command(dof), qdd(dof);
  for (Eigen::Index k = 0; k < n; ++k) {
    command = ctl.feedforward == Feedforward::kModel
                  ? dyn.torque(ref.q_rad.row(k).transpose(), ref.qd_radps.row(k).transpose(), ref.qdd_radps2.row(k).transpose())
                  : Eigen::VectorXd::Zero(dof);
    command += ctl.kp_Nm_per_rad.cwiseProduct(ref.q_rad.row(k).transpose() - q) + ctl.kd_Nms_per_rad.cwiseProduct(ref.qd_radps.row(k).transpose() - qd);
    if (k == 0 || ctl.actuator_bandwidth_hz <= 0.0) motor = command;  // at rest on the reference at t = 0: no start transient
    for (int sub = 0; sub < substeps; ++sub) {
      const Eigen::LLT<Eigen::MatrixXd> llt(dyn.mass(q));
      if (llt.info() != Eigen::Success) {
        run.message = "the model's mass matrix is not positive definite" + at(ref.t_s[k]);
        return run;
      }
      qdd = llt.solve(motor - dyn.torque(q, qd, Eigen::VectorXd::Zero(dof)));
      if (sub == 0) {
        s.q_rad.row(k) = q.transpose();
        s.qd_radps.row(k) = qd.transpose();
        s.qdd_radps2.row(k) = qdd.transpose();
        s.tau_Nm.row(k) = motor.transpose();
      }
      qd += h * qdd;
      q += h * qd;
      if (ctl.actuator_bandwidth_hz > 0.0) motor += lag * (command - motor);
    }
    if (k + 1 < n && !((q - ref.q_rad.row(k + 1).transpose()).cwiseAbs().maxCoeff() <= 1.0)) {
      run.message = "the model leaves its reference by more than 1 rad" + at(ref.t_s[k + 1]);
      return run;
    }
  }
  run.ok = true;
  return run;
}

}  // namespace exoid::ident
