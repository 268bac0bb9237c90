#include "exoid/ident/signals/joint_signals.hpp"

#include "exoid/core/format.hpp"

#include <stdexcept>

namespace exoid::ident {

void JointSignals::validate() const {
  const Eigen::Index n = t_s.size();
  if (q_rad.rows() != n || qd_radps.rows() != n || qdd_radps2.rows() != n || tau_Nm.rows() != n) {
    throw std::invalid_argument("joint signals: expected " + core::toText(n) +
                                " rows in q, qd, qdd and tau, got " + core::toText(q_rad.rows()) +
                                ", " + core::toText(qd_radps.rows()) + ", " +
                                core::toText(qdd_radps2.rows()) + ", " +
                                core::toText(tau_Nm.rows()));
  }
  const Eigen::Index dof = q_rad.cols();
  if (dof < 1 || qd_radps.cols() != dof || qdd_radps2.cols() != dof || tau_Nm.cols() != dof) {
    throw std::invalid_argument("joint signals: expected the same number of joints (>= 1) in q, qd, qdd and tau, got " +
                                core::toText(dof) + ", " + core::toText(qd_radps.cols()) + ", " +
                                core::toText(qdd_radps2.cols()) + ", " + core::toText(tau_Nm.cols()));
  }
  if (base.rows() != 0 && base.rows() != n) {
    throw std::invalid_argument("joint signals: expected 0 or " + core::toText(n) + " rows of base motion, got " +
                                core::toText(base.rows()));
  }
  if (!t_s.allFinite() || !q_rad.allFinite() || !qd_radps.allFinite() || !qdd_radps2.allFinite() ||
      !tau_Nm.allFinite() || !base.allFinite()) {
    throw std::invalid_argument("joint signals contain a NaN or Inf value");
  }
}

}  // namespace exoid::ident
