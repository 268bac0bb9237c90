#include "exoid/ident/signals/sampled_reference.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/signals/signals.hpp"

#include <cmath>
#include <stdexcept>

namespace exoid::ident {

void SampledReference::validate() const {
  const Eigen::Index n = t_s.size();
  for (const Eigen::MatrixXd* m : {&q_rad, &qd_radps, &qdd_radps2}) {
    if (m->rows() != n || m->cols() != q_rad.cols()) {
      throw std::invalid_argument("reference: t, q, qd and qdd must have the same number of samples (and q, qd, qdd of joints)");
    }
  }
  if (n < 5) throw std::invalid_argument("reference: need >= 5 samples, got " + core::toText(n));
  if (!t_s.allFinite() || !q_rad.allFinite() || !qd_radps.allFinite() || !qdd_radps2.allFinite()) {
    throw std::invalid_argument("reference contains a NaN or Inf value");
  }
  const double dt = (t_s[n - 1] - t_s[0]) / static_cast<double>(n - 1);
  if (!(dt > 0.0)) throw std::invalid_argument("reference: time must increase");
  for (Eigen::Index i = 1; i < n; ++i) {
    if (!(std::abs(t_s[i] - t_s[i - 1] - dt) <= 1e-3 * dt)) {
      throw std::invalid_argument("reference: sampling is not uniform at sample " + core::toText(i));
    }
  }
}

SampledReference SampledReference::fromAngles(const Eigen::VectorXd& t_s, const Eigen::MatrixXd& q_ref_rad) {
  if (t_s.size() != q_ref_rad.rows() || t_s.size() < 5) {
    throw std::invalid_argument("reference: need >= 5 samples of t and of every reference angle");
  }
  SampledReference r;
  r.t_s = t_s;
  r.q_rad = q_ref_rad;
  const double dt = (t_s[t_s.size() - 1] - t_s[0]) / static_cast<double>(t_s.size() - 1);
  r.qd_radps = differentiate(q_ref_rad, dt, Differentiation::kCentral4);
  r.qdd_radps2 = differentiate(r.qd_radps, dt, Differentiation::kCentral4);
  r.validate();
  return r;
}

}  // namespace exoid::ident
