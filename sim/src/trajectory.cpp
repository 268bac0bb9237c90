#include "exoid/sim/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace exoid::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

void checkJoint(const FourierJoint& j, const char* name) {
  auto bad = [&](const std::string& what) {
    throw std::invalid_argument(std::string("'fourier.") + name + "': " + what);
  };
  if (!std::isfinite(j.offset_rad)) bad("offset_rad must be finite");
  if (j.a_rad.size() != j.b_rad.size()) {
    std::ostringstream ss;
    ss << "a_rad and b_rad must have the same number of harmonics, got " << j.a_rad.size()
       << " and " << j.b_rad.size();
    bad(ss.str());
  }
  for (double v : j.a_rad) if (!std::isfinite(v)) bad("a_rad must be finite");
  for (double v : j.b_rad) if (!std::isfinite(v)) bad("b_rad must be finite");
}

double smoothstep(double x, double& d1, double& d2) {
  if (x >= 1) {
    d1 = d2 = 0;
    return 1;
  }
  const double x2 = x * x, x3 = x2 * x;
  d1 = 30 * x2 - 60 * x3 + 30 * x2 * x2;
  d2 = 60 * x - 180 * x2 + 120 * x3;
  return 10 * x3 - 15 * x2 * x2 + 6 * x3 * x2;
}

}  // namespace

void FourierSpec::validate() const {
  if (!std::isfinite(base_frequency_Hz) || base_frequency_Hz <= 0) {
    std::ostringstream ss;
    ss << "'fourier.base_frequency_Hz' must be > 0, got " << base_frequency_Hz;
    throw std::invalid_argument(ss.str());
  }
  checkJoint(hip, "hip");
  checkJoint(knee, "knee");
  if (lock_hip) {
    for (std::size_t k = 0; k < hip.a_rad.size(); ++k) {
      if (hip.a_rad[k] != 0 || hip.b_rad[k] != 0) {
        throw std::invalid_argument("'fourier.lock_hip': a locked hip must have zero harmonics");
      }
    }
  }
}

FourierSpec paperTrajectory(int id) {
  FourierSpec s;
  s.base_frequency_Hz = 1.0;
  const double A = 30 * kDeg;
  switch (id) {
    case 1:
      s.hip = {-10 * kDeg, {}, {}};
      s.knee = {45 * kDeg, {0.0}, {-A}};
      s.lock_hip = true;
      break;
    case 2:
      s.hip = {-10 * kDeg, {}, {}};
      s.knee = {60 * kDeg, {0.0}, {-A}};
      s.lock_hip = true;
      break;
    case 3:
      s.hip = {-30 * kDeg, {0.0}, {-A}};
      s.knee = {75 * kDeg, {0.0}, {-A}};
      break;
    case 4:
      s.hip = {-45 * kDeg, {0.0}, {-A}};
      s.knee = {60 * kDeg, {0.0}, {A}};
      break;
    default: {
      std::ostringstream ss;
      ss << "'trajectory' must be 1, 2, 3 or 4 (paper Table 1) or 0 (Fourier), got " << id;
      throw std::invalid_argument(ss.str());
    }
  }
  return s;
}

Trajectory::Trajectory(FourierSpec spec, double ramp_s) : spec_(std::move(spec)), ramp_s_(ramp_s) {
  spec_.validate();
  if (!std::isfinite(ramp_s) || ramp_s < 0) {
    std::ostringstream ss;
    ss << "'ramp_s' must be >= 0, got " << ramp_s;
    throw std::invalid_argument(ss.str());
  }
  JointReference r;
  raw(0.0, r);
  q0_ = r.q;
}

void Trajectory::raw(double t, JointReference& out) const {
  const double w = 2 * M_PI * spec_.base_frequency_Hz;
  out.q = {spec_.hip.offset_rad, spec_.knee.offset_rad};
  out.qd.setZero();
  out.qdd.setZero();
  const std::size_t nh = std::max(spec_.hip.a_rad.size(), spec_.knee.a_rad.size());
  for (std::size_t k = 0; k < nh; ++k) {
    // One sin/cos per harmonic, shared by both joints.
    const double wk = w * static_cast<double>(k + 1);
    const double c = std::cos(wk * t), s = std::sin(wk * t);
    const FourierJoint* joints[2] = {&spec_.hip, &spec_.knee};
    for (int j = 0; j < 2; ++j) {
      const FourierJoint& J = *joints[j];
      if (k >= J.a_rad.size()) continue;
      const double a = J.a_rad[k], b = J.b_rad[k];
      out.q[j] += a * c + b * s;
      out.qd[j] += wk * (-a * s + b * c);
      out.qdd[j] += -wk * wk * (a * c + b * s);
    }
  }
}

JointReference Trajectory::at(double t_s) const {
  JointReference r;
  raw(t_s, r);
  if (ramp_s_ > 0 && t_s < ramp_s_) {
    double s1, s2;
    const double x = t_s < 0 ? 0.0 : t_s / ramp_s_;
    const double s = smoothstep(x, s1, s2);
    s1 /= ramp_s_;
    s2 /= ramp_s_ * ramp_s_;
    const Eigen::Vector2d dq = r.q - q0_;
    r.qdd = s2 * dq + 2 * s1 * r.qd + s * r.qdd;
    r.qd = s1 * dq + s * r.qd;
    r.q = q0_ + s * dq;
  }
  return r;
}

}  // namespace exoid::sim
