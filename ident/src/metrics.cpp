#include "exoid/ident/metrics.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace exoid::ident {

TorqueErrorStats torqueError(const Eigen::Ref<const Eigen::VectorXd>& measured,
                             const Eigen::Ref<const Eigen::VectorXd>& predicted) {
  if (measured.size() != predicted.size() || measured.size() == 0) {
    throw std::invalid_argument("torque error: sizes " + std::to_string(measured.size()) + " and " +
                                std::to_string(predicted.size()) + " must agree and be > 0");
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
    throw std::invalid_argument("parameter error: estimate has " + std::to_string(estimate.size()) +
                                " entries, truth " + std::to_string(truth.size()));
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

}  // namespace exoid::ident
