#include "exoid/ident/model/closed_loop.hpp"

#include "exoid/core/format.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace exoid::ident {

Feedforward parseFeedforward(const std::string& name) {
  if (name == "model") return Feedforward::kModel;
  if (name == "none") return Feedforward::kNone;
  throw std::invalid_argument("unknown feedforward '" + name + "' (expected none or model)");
}

namespace {
[[noreturn]] void bad(const std::string& field, double value, const char* expected) {
  std::ostringstream ss;
  ss.precision(17);
  ss << "controller: '" << field << "' must be " << expected << ", got " << value;
  throw std::invalid_argument(ss.str());
}
}  // namespace

void Controller::validate(const std::vector<std::string>& joints) const {
  const auto n = static_cast<Eigen::Index>(joints.size());
  const auto gains = [&](const Eigen::VectorXd& v, const char* name, bool optional) {
    if (optional && v.size() == 0) return;
    if (v.size() != n) {
      throw std::invalid_argument(std::string("controller: '") + name + "' has " + core::toText(v.size()) + " values; the robot has " +
                                  core::toText(n) + " joints");
    }
    for (Eigen::Index j = 0; j < n; ++j) {
      if (!(std::isfinite(v[j]) && v[j] >= 0)) bad(std::string(name) + "[" + joints[static_cast<std::size_t>(j)] + "]", v[j], "finite and >= 0");
    }
  };
  gains(kp_Nm_per_rad, "kp", false);
  gains(ki_Nm_per_rad_s, "ki", true);
  gains(kd_Nms_per_rad, "kd", false);
  if (!(std::isfinite(derivative_cutoff_hz) && derivative_cutoff_hz >= 0)) bad("derivative_cutoff_hz", derivative_cutoff_hz, ">= 0 (0 = unfiltered)");
  if (!(integral_limit_Nm > 0)) bad("integral_limit_Nm", integral_limit_Nm, "> 0");
  if (!(std::isfinite(actuator_bandwidth_hz) && actuator_bandwidth_hz >= 0.0)) bad("actuator_bandwidth_hz", actuator_bandwidth_hz, "finite and >= 0");
  if (!locked.empty() && static_cast<Eigen::Index>(locked.size()) != n) {
    throw std::invalid_argument("controller: 'locked' has " + core::toText(locked.size()) + " entries; the robot has " + core::toText(n) +
                                " joints");
  }
  bool any_free = false;
  for (Eigen::Index j = 0; j < n; ++j) {
    if (isLocked(static_cast<int>(j))) continue;
    any_free = true;
    if (!(kp_Nm_per_rad[j] > 0)) {
      bad("kp[" + joints[static_cast<std::size_t>(j)] + "]", kp_Nm_per_rad[j],
          "> 0 for a joint that is not locked (nothing else holds it on the reference)");
    }
  }
  if (!any_free) throw std::invalid_argument("controller: every joint is locked: nothing moves");
}

namespace {

// The model's dynamics from its rows: tau = M(q) qdd + h(q, qd).
class Dynamics {
 public:
  Dynamics(const Robot& robot, const Eigen::VectorXd& theta) : robot_(robot), theta_(theta) {}
  Eigen::VectorXd torque(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    return robotTorque(robot_, q, qd, qdd, theta_, work_);
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
  const Robot& robot_;
  const Eigen::VectorXd& theta_;
  RobotWorkspace work_;
};

std::string at(double t) {
  std::ostringstream ss;
  ss.precision(6);
  ss << " at t = " << t << " s";
  return ss.str();
}

// A loop this stiff against the model's inertia (e.g. the gains of a locked joint, tuned to a
// lock's 1e9 kg m^2) is no rig's: refused rather than integrated for hours.
constexpr double kMaxSubsteps = 1000.0;

// Substeps per sample for the stiffest loop at the start, omega = max(sqrt(kp / Mjj), kd / Mjj)
// over the free joints, so that omega h <= 0.05; 0 (message set) when a free joint's Mjj is not
// positive there or the loop is too stiff.
int substepsAtStart(Dynamics& dyn, const Controller& ctl, const Eigen::VectorXd& q0, double dt, double t0, std::string& message) {
  const Eigen::MatrixXd m0 = dyn.mass(q0);
  double omega = 0.0;
  for (int j = 0; j < q0.size(); ++j) {
    if (ctl.isLocked(j)) continue;
    if (!(m0(j, j) > 0)) {
      message = "the model's mass matrix is not positive definite (M" + core::toText(j + 1) + core::toText(j + 1) + " = " +
                core::toText(m0(j, j)) + at(t0) + ")";
      return 0;
    }
    omega = std::max({omega, std::sqrt(ctl.kp_Nm_per_rad[j] / m0(j, j)), ctl.kd_Nms_per_rad[j] / m0(j, j)});
  }
  if (!(omega * dt / 0.05 <= kMaxSubsteps)) {
    message = "the controller's loop is too stiff for the model (" + core::toText(omega) + " rad/s: over " +
              core::toText(static_cast<long>(kMaxSubsteps)) + " substeps per sample; gains of a locked joint?)";
    return 0;
  }
  return std::max(1, static_cast<int>(std::ceil(omega * dt / 0.05)));
}

// The rig's feedback law (core::PidController) from the controller's description: an empty ki is
// no integral term.
core::PidGains pidGains(const Controller& ctl) {
  core::PidGains g;
  g.kp_Nm_per_rad = ctl.kp_Nm_per_rad;
  g.ki_Nm_per_rad_s = ctl.ki_Nm_per_rad_s.size() > 0 ? ctl.ki_Nm_per_rad_s : Eigen::VectorXd::Zero(ctl.kp_Nm_per_rad.size());
  g.kd_Nms_per_rad = ctl.kd_Nms_per_rad;
  g.derivative = ctl.derivative;
  g.derivative_cutoff_Hz = ctl.derivative_cutoff_hz;
  // No limit (inf, which a controller file may say) is the largest one.
  g.integral_limit_Nm = std::min(ctl.integral_limit_Nm, std::numeric_limits<double>::max());
  return g;
}

// The controller at the samples: the feedforward plus the rig's PID on the tracking error, held
// until the next sample.
class SampledController {
 public:
  SampledController(const Controller& ctl, Dynamics& dyn, const Reference& ref, double dt, const Eigen::VectorXd& q0)
      : ctl_(ctl), dyn_(dyn), ref_(ref), pid_(pidGains(ctl), dt) {
    // As if the controller had held the initial pose before the record: an integral term holds the
    // gravity torque the feedforward leaves to it (all of it without feedforward, none with the
    // model's own); without an integral term nothing is preloaded.
    Eigen::VectorXd integral0 = Eigen::VectorXd::Zero(q0.size());
    if (ctl.feedforward == Feedforward::kNone && ctl.ki_Nm_per_rad_s.size() > 0) {
      const Eigen::VectorXd zero = Eigen::VectorXd::Zero(q0.size());
      const Eigen::VectorXd gravity = dyn.torque(q0, zero, zero);
      for (Eigen::Index j = 0; j < q0.size(); ++j) {
        if (ctl.ki_Nm_per_rad_s[j] > 0) integral0[j] = gravity[j];
      }
    }
    pid_.reset(std::vector<bool>(static_cast<std::size_t>(q0.size()), true), integral0);
  }

  // The command at sample i, the joints at (q, qd).
  Eigen::VectorXd update(Eigen::Index i, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
    Eigen::VectorXd u = ctl_.feedforward == Feedforward::kNone
                            ? Eigen::VectorXd(Eigen::VectorXd::Zero(q.size()))
                            : dyn_.torque(ref_.q_rad.row(i).transpose(), ref_.qd_radps.row(i).transpose(), ref_.qdd_radps2.row(i).transpose());
    pid_.update(ref_.q_rad.row(i).transpose(), ref_.qd_radps.row(i).transpose(), q, qd, u);
    return u;
  }

 private:
  const Controller& ctl_;
  Dynamics& dyn_;
  const Reference& ref_;
  core::PidController pid_;
};

// The robot between two samples: semi-implicit Euler substeps of the free joints under the motor
// torque (which follows the held command through its lag); locked joints follow the reference,
// interpolated within the sample.
class SampleIntegrator {
 public:
  SampleIntegrator(Dynamics& dyn, const Reference& ref, const Controller& ctl, int substeps, double h)
      : dyn_(dyn), ref_(ref), ctl_(ctl), substeps_(substeps), h_(h),
        lag_(ctl.actuator_bandwidth_hz > 0.0 ? 1.0 - std::exp(-2.0 * M_PI * ctl.actuator_bandwidth_hz * h) : 1.0) {
    for (int j = 0; j < ref.q_rad.cols(); ++j) {
      if (!ctl.isLocked(j)) free_.push_back(j);
    }
  }

  // From (q, qd) at sample i to the next; row i of `s` gets the state at the sample and the motor
  // torque. false (message set) when the mass matrix is not positive definite.
  bool step(Eigen::Index i, const Eigen::VectorXd& command, Eigen::VectorXd& motor, Eigen::VectorXd& q, Eigen::VectorXd& qd,
            JointSignals& s, std::string& message) {
    Eigen::VectorXd qdd = Eigen::VectorXd::Zero(q.size());
    for (int k = 0; k < substeps_; ++k) {
      followLocked(i, k, q, qd, qdd);
      if (!accelerate(q, qd, motor, qdd)) {
        message = "the model's mass matrix is not positive definite" + at(ref_.t_s[i]);
        return false;
      }
      if (k == 0) {
        s.q_rad.row(i) = q.transpose();
        s.qd_radps.row(i) = qd.transpose();
        s.qdd_radps2.row(i) = qdd.transpose();
        s.tau_Nm.row(i) = motor.transpose();
      }
      for (const int j : free_) {
        qd[j] += h_ * qdd[j];
        q[j] += h_ * qd[j];
      }
      if (ctl_.actuator_bandwidth_hz > 0.0) motor += lag_ * (command - motor);
    }
    return true;
  }

 private:
  void followLocked(Eigen::Index i, int k, Eigen::VectorXd& q, Eigen::VectorXd& qd, Eigen::VectorXd& qdd) const {
    for (int j = 0; j < q.size(); ++j) {
      if (!ctl_.isLocked(j)) continue;
      const Eigen::Index i1 = std::min<Eigen::Index>(i + 1, ref_.size() - 1);
      const double w = static_cast<double>(k) / substeps_;
      q[j] = (1 - w) * ref_.q_rad(i, j) + w * ref_.q_rad(i1, j);
      qd[j] = (1 - w) * ref_.qd_radps(i, j) + w * ref_.qd_radps(i1, j);
      qdd[j] = (1 - w) * ref_.qdd_radps2(i, j) + w * ref_.qdd_radps2(i1, j);
    }
  }

  // M qdd = u - h over the free joints, the locked joints' accelerations given in qdd; false when
  // M is not positive definite on the free joints.
  bool accelerate(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& u, Eigen::VectorXd& qdd) {
    const Eigen::MatrixXd m = dyn_.mass(q);
    Eigen::VectorXd qdd_locked = qdd;
    for (const int j : free_) qdd_locked[j] = 0.0;
    const Eigen::VectorXd rhs = u - dyn_.torque(q, qd, qdd_locked);
    if (free_.size() == 1) {  // one equation: solved as it stands
      const int j = free_.front();
      if (!(m(j, j) > 0)) return false;
      qdd[j] = rhs[j] / m(j, j);
      return true;
    }
    const Eigen::MatrixXd m_free = m(free_, free_);
    const Eigen::LLT<Eigen::MatrixXd> llt(m_free);
    if (llt.info() != Eigen::Success || !(llt.matrixLLT().diagonal().array() > 0).all()) return false;
    const Eigen::VectorXd solved = llt.solve(Eigen::VectorXd(rhs(free_)));
    for (std::size_t a = 0; a < free_.size(); ++a) qdd[free_[a]] = solved[static_cast<Eigen::Index>(a)];
    return true;
  }

  Dynamics& dyn_;
  const Reference& ref_;
  const Controller& ctl_;
  std::vector<int> free_;
  int substeps_;
  double h_, lag_;
};

// false (message set) when a joint is more than 1 rad off the reference at sample i1.
bool onTrack(const Robot& robot, const Eigen::VectorXd& q, const Reference& ref, Eigen::Index i1, std::string& message) {
  for (int j = 0; j < q.size(); ++j) {
    if (!(std::abs(q[j] - ref.q_rad(i1, j)) <= 1.0)) {
      message = "the model cannot follow the reference: the " + robot.chain.joints[static_cast<std::size_t>(j)].name +
                " is more than 1 rad off" + at(ref.t_s[i1]);
      return false;
    }
  }
  return true;
}

JointSignals sized(const Eigen::VectorXd& t_s, Eigen::Index dof) {
  JointSignals s;
  s.t_s = t_s;
  s.q_rad.resize(t_s.size(), dof);
  s.qd_radps.resize(t_s.size(), dof);
  s.qdd_radps2.resize(t_s.size(), dof);
  s.tau_Nm.resize(t_s.size(), dof);
  return s;
}

}  // namespace

ClosedLoopRun simulateClosedLoop(const Robot& robot, const Eigen::VectorXd& theta, const Controller& ctl, const Reference& ref) {
  ctl.validate(robot.jointNames());
  ref.validate();
  const int dof = robot.dof();
  if (ref.q_rad.cols() != dof || theta.size() != robot.parameters()) {
    throw std::invalid_argument("closed loop: the reference has " + core::toText(ref.q_rad.cols()) + " joints and theta " +
                                core::toText(theta.size()) + " values; the robot " + core::toText(dof) + " joints and " +
                                core::toText(robot.parameters()) + " parameters");
  }
  if (!theta.allFinite()) throw std::invalid_argument("closed loop: the parameters contain a NaN or Inf value");
  Dynamics dyn(robot, theta);
  const Eigen::Index n = ref.size();
  const double dt = (ref.t_s[n - 1] - ref.t_s[0]) / static_cast<double>(n - 1);

  ClosedLoopRun run;
  run.states = sized(ref.t_s, dof);
  Eigen::VectorXd q = ref.q_rad.row(0).transpose(), qd = ref.qd_radps.row(0).transpose();
  const int substeps = substepsAtStart(dyn, ctl, q, dt, ref.t_s[0], run.message);
  if (substeps == 0) return run;
  SampledController controller(ctl, dyn, ref, dt, q);
  SampleIntegrator integrator(dyn, ref, ctl, substeps, dt / substeps);
  Eigen::VectorXd motor;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::VectorXd command = controller.update(i, q, qd);
    if (i == 0 || ctl.actuator_bandwidth_hz <= 0.0) motor = command;  // at rest on the reference at t = 0: no start transient
    if (!integrator.step(i, command, motor, q, qd, run.states, run.message)) return run;
    if (!onTrack(robot, q, ref, std::min<Eigen::Index>(i + 1, n - 1), run.message)) return run;
  }
  run.ok = true;
  return run;
}

}  // namespace exoid::ident
