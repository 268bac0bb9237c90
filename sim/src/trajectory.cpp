#include "exoid/sim/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace exoid::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

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

core::FourierSeries paperTrajectory(int id) {
  core::FourierSeries s = core::FourierSeries::still(2, 1, 1.0);
  const double A = 30 * kDeg;
  switch (id) {
    case 1:
      s.offset_rad << -10 * kDeg, 45 * kDeg;
      s.b_rad << 0.0, -A;
      s.locked_joints = 1;
      break;
    case 2:
      s.offset_rad << -10 * kDeg, 60 * kDeg;
      s.b_rad << 0.0, -A;
      s.locked_joints = 1;
      break;
    case 3:
      s.offset_rad << -30 * kDeg, 75 * kDeg;
      s.b_rad << -A, -A;
      break;
    case 4:
      s.offset_rad << -45 * kDeg, 60 * kDeg;
      s.b_rad << -A, A;
      break;
    default: {
      std::ostringstream ss;
      ss << "'trajectory' must be 1, 2, 3 or 4 (paper Table 1) or 0 (Fourier), got " << id;
      throw std::invalid_argument(ss.str());
    }
  }
  return s;
}

Trajectory::Trajectory(core::FourierSeries spec, double ramp_s) : spec_(std::move(spec)), ramp_s_(ramp_s) {
  spec_.validate();
  if (spec_.dof() != 2 || spec_.locked_joints > 1) {
    throw std::invalid_argument("'fourier': the APAL leg's trajectory moves two joints, hip and knee (the hip locked or not)");
  }
  if (!std::isfinite(ramp_s) || ramp_s < 0) {
    std::ostringstream ss;
    ss << "'ramp_s' must be >= 0, got " << ramp_s;
    throw std::invalid_argument(ss.str());
  }
  JointReference r;
  raw(0.0, r);
  q0_ = r.q;
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
