#include "exoid/ident/leg/regressor.hpp"

#include "exoid/core/format.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace exoid::ident {

void LegConstants::validate() const {
  if (!(std::isfinite(thigh_length_m) && thigh_length_m > 0.0)) {
    throw std::invalid_argument("thigh length must be finite and > 0 m, got " +
                                core::toText(thigh_length_m));
  }
  if (!(std::isfinite(gravity_mps2) && gravity_mps2 > 0.0)) {
    throw std::invalid_argument("gravity must be finite and > 0 m/s^2, got " +
                                core::toText(gravity_mps2));
  }
}

void regressorRows(const LegConstants& c, const Eigen::Vector2d& q, const Eigen::Vector2d& qd,
                   const Eigen::Vector2d& qdd, RegressorRow& hip, RegressorRow& knee) {
  regressorRows(c, q, qd, qdd, BaseMotion::still(c.gravity_mps2), hip, knee);
}

void regressorRows(const LegConstants& c, const Eigen::Vector2d& q, const Eigen::Vector2d& qd_rel,
                   const Eigen::Vector2d& qdd_rel, const BaseMotion& base, RegressorRow& hip, RegressorRow& knee) {
  const double Lt = c.thigh_length_m;
  // Absolute rates for the inertial terms (the thigh turns with the base).
  const Eigen::Vector2d qd(qd_rel[0] + base.omega_radps, qd_rel[1]);
  const Eigen::Vector2d qdd(qdd_rel[0] + base.alpha_radps2, qdd_rel[1]);
  const double s1 = std::sin(q[0]), c1 = std::cos(q[0]);
  const double s2 = std::sin(q[1]), c2 = std::cos(q[1]);
  const double s12 = std::sin(q[0] + q[1]), c12 = std::cos(q[0] + q[1]);
  // The field's terms: g sin(th) -> f_z sin(th) - f_x cos(th), g cos(th) -> f_z cos(th) + f_x sin(th).
  const double fx = base.f_x_mps2, fz = base.f_z_mps2;
  const double gs1 = fz * s1 - fx * c1, gc1 = fz * c1 + fx * s1;
  const double gs12 = fz * s12 - fx * c12, gc12 = fz * c12 + fx * s12;
  const double a = -qd[1] * (2.0 * qd[0] + qd[1]);  // qd1^2 - (qd1 + qd2)^2
  const double b = 2.0 * qdd[0] + qdd[1];
  hip << gs1, gc1, qdd[0], sgn(qd_rel[0]), qd_rel[0],
      Lt * (b * c2 + a * s2) + gs12,
      Lt * (-b * s2 + a * c2) + gc12,
      qdd[1],
      // The paper prints sgn(qd1), qd1 here; knee friction does not act on the hip equation.
      0.0, 0.0;
  const double qd1sq = qd[0] * qd[0];
  // The print garbles the Mys entry; this is the Lagrange-derived form (paper.md).
  knee << 0.0, 0.0, 0.0, 0.0, 0.0,
      Lt * (qdd[0] * c2 + qd1sq * s2) + gs12,
      Lt * (-qdd[0] * s2 + qd1sq * c2) + gc12,
      qdd[0] + qdd[1], sgn(qd_rel[1]), qd_rel[1];
}

namespace {
template <typename Fn>
void forEachSample(const JointSignals& s, const LegConstants& c, Fn&& fn) {
  c.validate();
  s.validate();
  if (s.q_rad.cols() != 2) {
    throw std::invalid_argument("the 2-link leg's regressor needs 2 joints (hip, knee), got " + core::toText(s.q_rad.cols()) +
                                ": a chain's signals go to the chain regressor (ident/model)");
  }
  RegressorRow hip, knee;
  const bool moving = s.base.rows() > 0;
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    const BaseMotion b = moving ? BaseMotion{s.base(i, 0), s.base(i, 1), s.base(i, 2), s.base(i, 3)}
                                : BaseMotion::still(c.gravity_mps2);
    regressorRows(c, s.q_rad.row(i).transpose(), s.qd_radps.row(i).transpose(), s.qdd_radps2.row(i).transpose(), b,
                  hip, knee);
    fn(i, hip, knee);
  }
}
}  // namespace

Eigen::MatrixXd jointRegressor(const JointSignals& s, Joint joint, const LegConstants& c) {
  Eigen::MatrixXd y(s.size(), kNumParams);
  forEachSample(s, c, [&](Eigen::Index i, const RegressorRow& hip, const RegressorRow& knee) {
    y.row(i) = joint == Joint::kHip ? hip : knee;
  });
  return y;
}

void nonzeroRegressorColumns(const JointSignals& s, const LegConstants& c, Eigen::Ref<Eigen::MatrixXd> out) {
  constexpr int kKneeColumns = kNumParams - kKneeFirstColumn;
  if (out.rows() != s.size() || out.cols() != kHipColumns + kKneeColumns) {
    throw std::invalid_argument("nonzeroRegressorColumns: the output must be " + core::toText(s.size()) + " x 13");
  }
  forEachSample(s, c, [&](Eigen::Index i, const RegressorRow& hip, const RegressorRow& knee) {
    out.row(i).head<kHipColumns>() = hip.head<kHipColumns>();
    out.row(i).tail<kKneeColumns>() = knee.tail<kKneeColumns>();
  });
}

Eigen::MatrixXd stackedRegressor(const JointSignals& s, const LegConstants& c) {
  Eigen::MatrixXd y(2 * s.size(), kNumParams);
  forEachSample(s, c, [&](Eigen::Index i, const RegressorRow& hip, const RegressorRow& knee) {
    y.row(2 * i) = hip;
    y.row(2 * i + 1) = knee;
  });
  return y;
}

Eigen::VectorXd stackedTorque(const JointSignals& s) {
  // Row-major copy of an N x dof matrix is the interleaved [hip_0, knee_0, hip_1, ...].
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows = s.tau_Nm;
  return Eigen::Map<const Eigen::VectorXd>(rows.data(), rows.size());
}

Eigen::MatrixX2d predictTorque(const JointSignals& s, const ParamVector& x, const LegConstants& c) {
  Eigen::MatrixX2d tau(s.size(), 2);
  forEachSample(s, c, [&](Eigen::Index i, const RegressorRow& hip, const RegressorRow& knee) {
    tau(i, 0) = hip.dot(x);
    tau(i, 1) = knee.dot(x);
  });
  return tau;
}

}  // namespace exoid::ident
