#include "exoid/ident/leg/closed_loop.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/signals/signals.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace exoid::ident {

const char* toString(Feedforward f) { return f == Feedforward::kModel ? "model" : "none"; }

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

void ControllerModel::validate() const {
  const char* joint[2] = {"[hip]", "[knee]"};
  for (int j = 0; j < 2; ++j) {
    if (!(std::isfinite(pid.kp_Nm_per_rad[j]) && pid.kp_Nm_per_rad[j] >= 0)) bad(std::string("kp") + joint[j], pid.kp_Nm_per_rad[j], "finite and >= 0");
    if (!(std::isfinite(pid.ki_Nm_per_rad_s[j]) && pid.ki_Nm_per_rad_s[j] >= 0)) bad(std::string("ki") + joint[j], pid.ki_Nm_per_rad_s[j], "finite and >= 0");
    if (!(std::isfinite(pid.kd_Nms_per_rad[j]) && pid.kd_Nms_per_rad[j] >= 0)) bad(std::string("kd") + joint[j], pid.kd_Nms_per_rad[j], "finite and >= 0");
  }
  if (!(std::isfinite(pid.derivative_cutoff_hz) && pid.derivative_cutoff_hz >= 0)) bad("derivative_cutoff_hz", pid.derivative_cutoff_hz, ">= 0 (0 = unfiltered)");
  if (!(pid.integral_limit_Nm > 0)) bad("integral_limit_Nm", pid.integral_limit_Nm, "> 0");
  for (int j = 0; j < 2; ++j) {
    if (!locked[static_cast<std::size_t>(j)] && !(pid.kp_Nm_per_rad[j] > 0)) {
      bad(std::string("kp") + joint[j], pid.kp_Nm_per_rad[j], "> 0 for a joint that is not locked (nothing else holds it on the reference)");
    }
  }
  if (locked[0] && locked[1]) throw std::invalid_argument("controller: both joints locked: nothing moves");
}

namespace {

// The model's dynamics from its regressor: tau = M(q) qdd + h(q, qd).
class RigidModel {
 public:
  RigidModel(const ParamVector& x, const LegConstants& c, double knee_armature) : x_(x), c_(c), ia2_(knee_armature) {}
  Eigen::Vector2d torque(const Eigen::Vector2d& q, const Eigen::Vector2d& qd, const Eigen::Vector2d& qdd) const {
    regressorRows(c_, q, qd, qdd, hip_, knee_);
    return {hip_.dot(x_), knee_.dot(x_) + ia2_ * qdd[1]};
  }
  Eigen::Matrix2d mass(const Eigen::Vector2d& q) const {
    const Eigen::Vector2d g = torque(q, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero());
    Eigen::Matrix2d m;
    m.col(0) = torque(q, Eigen::Vector2d::Zero(), Eigen::Vector2d::UnitX()) - g;
    m.col(1) = torque(q, Eigen::Vector2d::Zero(), Eigen::Vector2d::UnitY()) - g;
    return m;
  }

 private:
  ParamVector x_;
  LegConstants c_;
  double ia2_;
  mutable RegressorRow hip_, knee_;
};

std::string at(double t) {
  std::ostringstream ss;
  ss.precision(6);
  ss << " at t = " << t << " s";
  return ss.str();
}

std::string notPositiveDefinite(int j, const std::string& what, double t) {
  return std::string("the model's mass matrix is not positive definite (M") + (j == 0 ? "11" : "22") + what + at(t) + ")";
}

// Substeps per sample for the stiffest loop at the start, omega = max(sqrt(kp / Mjj), kd / Mjj),
// so that omega h <= 0.05; 0 (message set) when a free joint's Mjj is not positive there.
int substepsAtStart(const RigidModel& model, const ControllerModel& ctl, const Eigen::Vector2d& q0, double dt, double t0,
                    std::string& message) {
  const Eigen::Matrix2d m0 = model.mass(q0);
  double omega = 0.0;
  for (int j = 0; j < 2; ++j) {
    if (ctl.locked[j]) continue;
    if (!(m0(j, j) > 0)) {
      message = notPositiveDefinite(j, " = " + core::toText(m0(j, j)), t0);
      return 0;
    }
    omega = std::max({omega, std::sqrt(ctl.pid.kp_Nm_per_rad[j] / m0(j, j)), ctl.pid.kd_Nms_per_rad[j] / m0(j, j)});
  }
  return std::max(1, static_cast<int>(std::ceil(omega * dt / 0.05)));
}

// The controller at the samples: the feedforward plus PID on the tracking error (derivative
// low-passed, integral clamped), held until the next sample.
class SampledController {
 public:
  SampledController(const ControllerModel& ctl, const RigidModel& model, const Reference& ref, double dt, const Eigen::Vector2d& q0)
      : ctl_(ctl), model_(model), ref_(ref), dt_(dt),
        alpha_(ctl.pid.derivative_cutoff_hz > 0 ? dt / (dt + 1.0 / (2 * M_PI * ctl.pid.derivative_cutoff_hz)) : 1.0) {
    // As if the controller had held the initial pose before the record: an integral term holds the
    // gravity torque the feedforward leaves to it (all of it without feedforward, none with the
    // model's own); without an integral term nothing is preloaded.
    if (ctl.feedforward == Feedforward::kNone) {
      const Eigen::Vector2d gravity = model.torque(q0, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero());
      for (int j = 0; j < 2; ++j) {
        if (ctl.pid.ki_Nm_per_rad_s[j] > 0) integral_[j] = std::clamp(gravity[j], -ctl.pid.integral_limit_Nm, ctl.pid.integral_limit_Nm);
      }
    }
  }

  // The torque at sample i, the joints at q.
  Eigen::Vector2d update(Eigen::Index i, const Eigen::Vector2d& q) {
    Eigen::Vector2d u = feedforward(i);
    const PidLaw& pid = ctl_.pid;
    for (int j = 0; j < 2; ++j) {
      const double e = ref_.q_rad(i, j) - q[j];
      const double e_dot_raw = i == 0 ? 0.0 : (e - e_prev_[j]) / dt_;
      e_dot_[j] += alpha_ * (e_dot_raw - e_dot_[j]);
      e_prev_[j] = e;
      if (i > 0) integral_[j] = std::clamp(integral_[j] + pid.ki_Nm_per_rad_s[j] * e * dt_, -pid.integral_limit_Nm, pid.integral_limit_Nm);
      u[j] += pid.kp_Nm_per_rad[j] * e + integral_[j] + pid.kd_Nms_per_rad[j] * e_dot_[j];
    }
    return u;
  }

 private:
  Eigen::Vector2d feedforward(Eigen::Index i) const {
    if (ctl_.feedforward == Feedforward::kNone) return Eigen::Vector2d::Zero();
    return model_.torque(ref_.q_rad.row(i).transpose(), ref_.qd_radps.row(i).transpose(), ref_.qdd_radps2.row(i).transpose());
  }

  const ControllerModel& ctl_;
  const RigidModel& model_;
  const Reference& ref_;
  double dt_, alpha_;
  Eigen::Vector2d integral_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d e_prev_ = Eigen::Vector2d::Zero(), e_dot_ = Eigen::Vector2d::Zero();
};

// The leg between two samples: semi-implicit Euler substeps of the free joints under the held
// torque; locked joints follow the reference, interpolated within the sample.
class SampleIntegrator {
 public:
  SampleIntegrator(const RigidModel& model, const Reference& ref, const ControllerModel& ctl, int substeps, double h)
      : model_(model), ref_(ref), free_joint_{!ctl.locked[0], !ctl.locked[1]}, substeps_(substeps), h_(h) {}

  // From (q, qd) at sample i to the next, under torque u; row i of `s` gets the state at the
  // sample and u. false (message set) when the mass matrix is not positive definite.
  bool step(Eigen::Index i, const Eigen::Vector2d& u, Eigen::Vector2d& q, Eigen::Vector2d& qd, JointSignals& s, std::string& message) const {
    Eigen::Vector2d qdd = Eigen::Vector2d::Zero();
    for (int k = 0; k < substeps_; ++k) {
      followLocked(i, k, q, qd, qdd);
      if (!accelerate(q, qd, u, qdd)) {
        message = notPositiveDefiniteMessage(ref_.t_s[i]);
        return false;
      }
      if (k == 0) {
        s.q_rad.row(i) = q.transpose();
        s.qd_radps.row(i) = qd.transpose();
        s.qdd_radps2.row(i) = qdd.transpose();
        s.tau_Nm.row(i) = u.transpose();
      }
      for (int j = 0; j < 2; ++j) {
        if (!free_joint_[j]) continue;
        qd[j] += h_ * qdd[j];
        q[j] += h_ * qd[j];
      }
    }
    return true;
  }

 private:
  void followLocked(Eigen::Index i, int k, Eigen::Vector2d& q, Eigen::Vector2d& qd, Eigen::Vector2d& qdd) const {
    for (int j = 0; j < 2; ++j) {
      if (free_joint_[j]) continue;
      const Eigen::Index i1 = std::min<Eigen::Index>(i + 1, ref_.size() - 1);
      const double w = static_cast<double>(k) / substeps_;
      q[j] = (1 - w) * ref_.q_rad(i, j) + w * ref_.q_rad(i1, j);
      qd[j] = (1 - w) * ref_.qd_radps(i, j) + w * ref_.qd_radps(i1, j);
      qdd[j] = (1 - w) * ref_.qdd_radps2(i, j) + w * ref_.qdd_radps2(i1, j);
    }
  }

  // M qdd = u - h over the free joints, the locked joints' accelerations given in qdd; false when
  // M is not positive definite (on the free joints).
  bool accelerate(const Eigen::Vector2d& q, const Eigen::Vector2d& qd, const Eigen::Vector2d& u, Eigen::Vector2d& qdd) const {
    const Eigen::Matrix2d m = model_.mass(q);
    Eigen::Vector2d qdd_free = qdd;
    for (int j = 0; j < 2; ++j) {
      if (free_joint_[j]) qdd_free[j] = 0.0;
    }
    const Eigen::Vector2d rhs = u - model_.torque(q, qd, qdd_free);
    if (free_joint_[0] && free_joint_[1]) {
      const Eigen::LLT<Eigen::Matrix2d> llt(m);
      if (llt.info() != Eigen::Success || !(m.determinant() > 0)) return false;
      qdd = llt.solve(rhs);
      return true;
    }
    const int j = free_joint_[0] ? 0 : 1;
    if (!(m(j, j) > 0)) return false;
    qdd[j] = rhs[j] / m(j, j);
    return true;
  }

  std::string notPositiveDefiniteMessage(double t) const {
    if (free_joint_[0] && free_joint_[1]) return "the model's mass matrix is not positive definite" + at(t);
    return notPositiveDefinite(free_joint_[0] ? 0 : 1, " <= 0", t);
  }

  const RigidModel& model_;
  const Reference& ref_;
  bool free_joint_[2];
  int substeps_;
  double h_;
};

// false (message set) when a joint is more than 1 rad off the reference at sample i1.
bool onTrack(const Eigen::Vector2d& q, const Reference& ref, Eigen::Index i1, std::string& message) {
  for (int j = 0; j < 2; ++j) {
    if (!(std::abs(q[j] - ref.q_rad(i1, j)) <= 1.0)) {
      message = std::string("the model cannot follow the reference: the ") + (j == 0 ? "hip" : "knee") + " is more than 1 rad off" +
                at(ref.t_s[i1]);
      return false;
    }
  }
  return true;
}

JointSignals sized(const Eigen::VectorXd& t_s) {
  JointSignals s;
  s.t_s = t_s;
  s.q_rad.resize(t_s.size(), 2);
  s.qd_radps.resize(t_s.size(), 2);
  s.qdd_radps2.resize(t_s.size(), 2);
  s.tau_Nm.resize(t_s.size(), 2);
  return s;
}

}  // namespace

ClosedLoopRun simulateClosedLoop(const ParamVector& x, const LegConstants& c, const ControllerModel& ctl,
                                 const Reference& ref, double knee_armature_kgm2) {
  c.validate();
  ctl.validate();
  ref.validate();
  if (!x.allFinite()) throw std::invalid_argument("closed loop: the parameters contain a NaN or Inf value");
  if (!std::isfinite(knee_armature_kgm2)) throw std::invalid_argument("closed loop: the knee armature is not finite");
  const RigidModel model(x, c, knee_armature_kgm2);
  const Eigen::Index n = ref.size();
  const double dt = (ref.t_s[n - 1] - ref.t_s[0]) / static_cast<double>(n - 1);

  ClosedLoopRun run;
  run.states = sized(ref.t_s);
  Eigen::Vector2d q = ref.q_rad.row(0).transpose(), qd = ref.qd_radps.row(0).transpose();
  const int substeps = substepsAtStart(model, ctl, q, dt, ref.t_s[0], run.message);
  if (substeps == 0) return run;
  SampledController controller(ctl, model, ref, dt, q);
  const SampleIntegrator integrator(model, ref, ctl, substeps, dt / substeps);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector2d u = controller.update(i, q);
    if (!integrator.step(i, u, q, qd, run.states, run.message)) return run;
    if (!onTrack(q, ref, std::min<Eigen::Index>(i + 1, n - 1), run.message)) return run;
  }
  run.ok = true;
  return run;
}

}  // namespace exoid::ident
