#include "exoid/ident/model/chain_regressor.hpp"

#include "exoid/core/format.hpp"

#include <Eigen/Geometry>

#include <stdexcept>

namespace exoid::ident {

namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return s;
}

// I v = L(v) [Ixx Ixy Ixz Iyy Iyz Izz]' for a symmetric I.
Eigen::Matrix<double, 3, 6> inertiaColumns(const Eigen::Vector3d& v) {
  Eigen::Matrix<double, 3, 6> L;
  L << v.x(), v.y(), v.z(), 0.0, 0.0, 0.0,  //
      0.0, v.x(), 0.0, v.y(), v.z(), 0.0,   //
      0.0, 0.0, v.x(), 0.0, v.y(), v.z();
  return L;
}

// The wrench (force; moment about the link frame's origin) a link needs for its motion, per
// standard parameter: f = m a + wd x mc + w x (w x mc), n = I wd + w x (I w) + mc x a.
Eigen::Matrix<double, 6, kLinkParams> linkWrenchColumns(const Eigen::Vector3d& w, const Eigen::Vector3d& wd,
                                                        const Eigen::Vector3d& a) {
  Eigen::Matrix<double, 6, kLinkParams> A = Eigen::Matrix<double, 6, kLinkParams>::Zero();
  const Eigen::Matrix3d W = skew(w);
  A.block<3, 1>(0, 0) = a;
  A.block<3, 3>(0, 1) = skew(wd) + W * W;
  A.block<3, 3>(3, 1) = -skew(a);
  A.block<3, 6>(3, 4) = inertiaColumns(wd) + W * inertiaColumns(w);
  return A;
}

void requireSize(const char* what, Eigen::Index got, int dof) {
  if (got != dof) {
    throw std::invalid_argument(std::string("chain regressor: expected ") + core::toText(dof) + " entries in " + what +
                                " (one per joint), got " + core::toText(static_cast<long long>(got)));
  }
}

}  // namespace

void chainRegressorInto(const ChainModel& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                        const Eigen::Ref<const Eigen::VectorXd>& qd, const Eigen::Ref<const Eigen::VectorXd>& qdd,
                        const ChainBaseMotion& base, ChainRegressorWorkspace& work, Eigen::Ref<Eigen::MatrixXd> out) {
  const int n = model.dof();
  requireSize("q", q.size(), n);
  requireSize("qd", qd.size(), n);
  requireSize("qdd", qdd.size(), n);
  const std::size_t un = static_cast<std::size_t>(n);
  if (work.R.size() != un) {
    work.R.resize(un);
    work.w.resize(un);
    work.wd.resize(un);
    work.a.resize(un);
  }
  work.wrench.setZero(6, kLinkParams * n);
  out.setZero();

  // Forward: each link's motion in its own frame.
  Eigen::Vector3d w = base.omega_radps, wd = base.alpha_radps2, a = base.specific_force_mps2;
  for (int i = 0; i < n; ++i) {
    const ChainJoint& j = model.joints[static_cast<std::size_t>(i)];
    const Eigen::Matrix3d R = j.parent_R_joint * Eigen::AngleAxisd(q[i], j.axis).toRotationMatrix();
    const Eigen::Vector3d& p = j.parent_p_joint_m;
    const Eigen::Vector3d a_joint = a + wd.cross(p) + w.cross(w.cross(p));  // the joint origin, parent frame
    const Eigen::Vector3d w_carried = R.transpose() * w;
    w = w_carried + j.axis * qd[i];
    wd = R.transpose() * wd + w_carried.cross(j.axis * qd[i]) + j.axis * qdd[i];
    a = R.transpose() * a_joint;
    const std::size_t ui = static_cast<std::size_t>(i);
    work.R[ui] = R;
    work.w[ui] = w;
    work.wd[ui] = wd;
    work.a[ui] = a;
  }

  // Backward: the wrench on each joint from every link beyond it, per parameter; the joint's
  // torque is its moment about the joint axis.
  const std::vector<JointParameterLayout> layout = model.layout();
  for (int i = n - 1; i >= 0; --i) {
    const std::size_t ui = static_cast<std::size_t>(i);
    const ChainJoint& j = model.joints[ui];
    const int cols = kLinkParams * (n - i);  // the links this joint carries: i .. n - 1
    auto carried = work.wrench.middleCols(kLinkParams * i, cols);
    carried.leftCols<kLinkParams>() += linkWrenchColumns(work.w[ui], work.wd[ui], work.a[ui]);
    const Eigen::RowVectorXd tau = j.axis.transpose() * carried.bottomRows<3>();
    for (int k = i; k < n; ++k) {
      out.block<1, kLinkParams>(i, layout[static_cast<std::size_t>(k)].link) = tau.segment<kLinkParams>(kLinkParams * (k - i));
    }
    if (j.friction) {
      out(i, layout[ui].friction) = (qd[i] > 0.0) - (qd[i] < 0.0);
      out(i, layout[ui].friction + 1) = qd[i];
    }
    if (j.armature) out(i, layout[ui].armature) = qdd[i];
    if (i == 0) break;
    // To the parent's frame: f' = R f, n' = R n + p x (R f).
    const Eigen::Matrix3d& R = work.R[ui];
    const Eigen::Matrix3d P = skew(j.parent_p_joint_m);
    const Eigen::MatrixXd f = R * carried.topRows<3>();
    carried.bottomRows<3>() = R * carried.bottomRows<3>() + P * f;
    carried.topRows<3>() = f;
  }
}

Eigen::MatrixXd chainRegressor(const ChainModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                               const Eigen::VectorXd& qdd, const ChainBaseMotion& base) {
  ChainRegressorWorkspace work;
  Eigen::MatrixXd out(model.dof(), model.standardParameterCount());
  chainRegressorInto(model, q, qd, qdd, base, work, out);
  return out;
}

Eigen::MatrixXd chainRegressor(const ChainModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                               const Eigen::VectorXd& qdd) {
  return chainRegressor(model, q, qd, qdd, ChainBaseMotion::still(model));
}

}  // namespace exoid::ident
