#include "exoid/ident/leg/metrics.hpp"

#include "exoid/core/format.hpp"
#include "exoid/core/random.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace exoid::ident {

TorqueErrorStats torqueError(const Eigen::Ref<const Eigen::VectorXd>& measured,
                             const Eigen::Ref<const Eigen::VectorXd>& predicted) {
  if (measured.size() != predicted.size() || measured.size() == 0) {
    throw std::invalid_argument("torque error: sizes " + core::toText(measured.size()) + " and " +
                                core::toText(predicted.size()) + " must agree and be > 0");
  }
  const Eigen::ArrayXd e = (measured - predicted).array().abs();
  const double n = static_cast<double>(e.size());
  TorqueErrorStats s;
  s.mean_abs = e.mean();
  s.std_abs = std::sqrt((e - s.mean_abs).square().sum() / n);
  s.rms = std::sqrt(e.square().sum() / n);
  s.max_abs = e.maxCoeff();
  return s;
}

ParamError paramError(const Eigen::Ref<const Eigen::VectorXd>& estimate,
                      const Eigen::Ref<const Eigen::VectorXd>& truth) {
  if (estimate.size() != truth.size() || truth.size() == 0) {
    throw std::invalid_argument("parameter error: estimate has " + core::toText(estimate.size()) +
                                " entries, truth " + core::toText(truth.size()));
  }
  if (truth.norm() == 0.0) throw std::invalid_argument("parameter error: truth vector is all zero");
  ParamError p;
  p.abs = estimate - truth;
  p.rel.resize(truth.size());
  for (Eigen::Index i = 0; i < truth.size(); ++i) {
    p.rel[i] = truth[i] != 0.0 ? p.abs[i] / std::abs(truth[i])
               : (p.abs[i] == 0.0 ? 0.0 : std::copysign(std::numeric_limits<double>::max(), p.abs[i]));
  }
  p.norm_rel = p.abs.norm() / truth.norm();
  p.max_abs_rel = p.rel.cwiseAbs().maxCoeff();
  return p;
}

JointSignals validationStates() {
  core::Rng rng(kValidationSeed);
  const double deg = M_PI / 180.0;
  JointSignals s;
  s.t_s = Eigen::VectorXd::LinSpaced(kValidationStates, 0.0, kValidationStates - 1.0);
  s.q_rad.resize(kValidationStates, 2);
  s.qd_radps.resize(kValidationStates, 2);
  s.qdd_radps2.resize(kValidationStates, 2);
  s.tau_Nm = Eigen::MatrixX2d::Zero(kValidationStates, 2);
  for (Eigen::Index i = 0; i < kValidationStates; ++i) {
    s.q_rad(i, 0) = rng.uniform(-90.0 * deg, 30.0 * deg);
    s.q_rad(i, 1) = rng.uniform(0.0, 110.0 * deg);
    for (int j = 0; j < 2; ++j) s.qd_radps(i, j) = rng.uniform(-3.0, 3.0);
    for (int j = 0; j < 2; ++j) s.qdd_radps2(i, j) = rng.uniform(-30.0, 30.0);
  }
  return s;
}

TorqueSpaceError torqueSpaceError(const ParamVector& estimate, const ParamVector& truth, const LegConstants& c) {
  static const JointSignals states = validationStates();
  const Eigen::MatrixXd Yh = jointRegressor(states, Joint::kHip, c), Yk = jointRegressor(states, Joint::kKnee, c);
  const ParamVector dx = estimate - truth;
  TorqueSpaceError e;
  e.hip = (Yh * dx).norm() / (Yh * truth).norm();
  e.knee = (Yk * dx).norm() / (Yk * truth).norm();
  return e;
}

}  // namespace exoid::ident
