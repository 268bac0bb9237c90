#include "exoid/core/fourier_series.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace exoid::core {

namespace {
constexpr double kTwoPi = 6.283185307179586;  // 2 pi, as 2 * M_PI rounds
}

FourierSeries FourierSeries::still(int dof, int harmonics, double f0_hz) {
  FourierSeries f;
  f.f0_hz = f0_hz;
  f.offset_rad = Eigen::VectorXd::Zero(dof);
  f.a_rad = Eigen::MatrixXd::Zero(harmonics, dof);
  f.b_rad = Eigen::MatrixXd::Zero(harmonics, dof);
  return f;
}

// Scalar loops in one fixed order of operations (the APAL rig's, the 2-link design's and the
// chain's evaluators all computed exactly these expressions): the designs call this millions of
// times, and a row of a column-major matrix is strided.
void FourierSeries::addHarmonic(int k, double w, double c, double s, Eigen::Ref<Eigen::VectorXd> q, Eigen::Ref<Eigen::VectorXd> qd,
                                Eigen::Ref<Eigen::VectorXd> qdd) const {
  const double minus_w_squared = -w * w;
  for (Eigen::Index j = 0; j < q.size(); ++j) {
    const double a = a_rad(k - 1, j), b = b_rad(k - 1, j);
    q[j] += a * c + b * s;
    qd[j] += w * (-a * s + b * c);
    qdd[j] += minus_w_squared * (a * c + b * s);
  }
}

void FourierSeries::addHarmonics(double t_s, Eigen::Ref<Eigen::VectorXd> q, Eigen::Ref<Eigen::VectorXd> qd,
                                 Eigen::Ref<Eigen::VectorXd> qdd) const {
  const double w0 = kTwoPi * f0_hz;
  for (int k = 1; k <= harmonics(); ++k) {
    const double w = w0 * static_cast<double>(k);
    addHarmonic(k, w, std::cos(w * t_s), std::sin(w * t_s), q, qd, qdd);
  }
}

void FourierSeries::validate() const {
  const auto bad = [](const std::string& what) { throw std::invalid_argument("trajectory: " + what); };
  if (!(f0_hz > 0.0 && std::isfinite(f0_hz))) bad("'f0_hz' must be > 0");
  if (dof() < 1) bad("no joints");
  if (a_rad.cols() != dof() || b_rad.cols() != dof() || a_rad.rows() != b_rad.rows()) {
    bad("'a_rad' and 'b_rad' must be harmonics x joints, one column per offset");
  }
  if (!offset_rad.allFinite() || !a_rad.allFinite() || !b_rad.allFinite()) bad("a NaN or Inf coefficient");
  if (locked_joints < 0 || locked_joints > dof()) bad("'locked_joints' must be in [0, " + std::to_string(dof()) + "]");
  for (int j = 0; j < locked_joints; ++j) {
    if (a_rad.col(j).cwiseAbs().maxCoeff() > 0.0 || b_rad.col(j).cwiseAbs().maxCoeff() > 0.0) {
      bad("joint " + std::to_string(j) + " is locked: its harmonics must be 0");
    }
  }
}

}  // namespace exoid::core
