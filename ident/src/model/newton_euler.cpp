#include "exoid/ident/model/newton_euler.hpp"

#include "exoid/core/format.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <stdexcept>

namespace exoid::ident {

namespace {

// v' L(x), where I x = L(x) [Ixx Ixy Ixz Iyy Iyz Izz]' for a symmetric I.
Eigen::Matrix<double, 1, 6> inertiaRow(const Eigen::Vector3d& v, const Eigen::Vector3d& x) {
  Eigen::Matrix<double, 1, 6> r;
  r << v.x() * x.x(), v.x() * x.y() + v.y() * x.x(), v.x() * x.z() + v.z() * x.x(), v.y() * x.y(),
      v.y() * x.z() + v.z() * x.y(), v.z() * x.z();
  return r;
}

// The rotation by q about a unit axis: written out for a coordinate axis (+-x, +-y, +-z: nearly
// every robot file's joints), Rodrigues' formula otherwise.
Eigen::Matrix3d rotationAbout(const Eigen::Vector3d& axis, double q) {
  const double c = std::cos(q), s = std::sin(q);
  Eigen::Matrix3d R;
  if (axis.y() == 0.0 && axis.z() == 0.0 && std::abs(axis.x()) == 1.0) {
    const double t = axis.x() * s;
    R << 1.0, 0.0, 0.0, 0.0, c, -t, 0.0, t, c;
  } else if (axis.x() == 0.0 && axis.z() == 0.0 && std::abs(axis.y()) == 1.0) {
    const double t = axis.y() * s;
    R << c, 0.0, t, 0.0, 1.0, 0.0, -t, 0.0, c;
  } else if (axis.x() == 0.0 && axis.y() == 0.0 && std::abs(axis.z()) == 1.0) {
    const double t = axis.z() * s;
    R << c, -t, 0.0, t, c, 0.0, 0.0, 0.0, 1.0;
  } else {
    R = Eigen::AngleAxisd(q, axis).toRotationMatrix();
  }
  return R;
}

// A link's motion in its own frame: angular velocity, angular acceleration, and the specific force
// (acceleration less gravity) at its origin.
struct LinkMotion {
  Eigen::Vector3d w, wd, a;
};

// The forward step both recursions share: the parent's motion carried across joint j at (q, qd,
// qdd) into the child's frame. Returns the parent-to-child rotation R (parent_R_joint turned by q).
Eigen::Matrix3d advance(const ChainJoint& j, double q, double qd, double qdd, LinkMotion& m) {
  // Most robot files place joint frames unrotated: skip the product then (same bits).
  const Eigen::Matrix3d turn = rotationAbout(j.axis, q);
  const Eigen::Matrix3d R = j.parent_R_joint.isIdentity(0.0) ? turn : Eigen::Matrix3d(j.parent_R_joint * turn);
  const Eigen::Vector3d& p = j.parent_p_joint_m;
  const Eigen::Vector3d a_joint = m.a + m.wd.cross(p) + m.w.cross(m.w.cross(p));  // the joint origin, parent frame
  const Eigen::Vector3d w_carried = R.transpose() * m.w;
  m.w = w_carried + j.axis * qd;
  m.wd = R.transpose() * m.wd + w_carried.cross(j.axis * qd) + j.axis * qdd;
  m.a = R.transpose() * a_joint;
  return R;
}

void requireSize(const char* what, Eigen::Index got, int dof) {
  if (got != dof) {
    throw std::invalid_argument(std::string("chain regressor: expected ") + core::toText(dof) + " entries in " + what +
                                " (one per joint), got " + core::toText(static_cast<long long>(got)));
  }
}

}  // namespace

// Link k needs the wrench (f; n about its origin), linear in its parameters phi_k:
//   f = m a + wd x mc + w x (w x mc),   n = I wd + w x (I w) + mc x a   (w, wd, a in its frame).
// Joint i (i <= k) carries it; its torque is the moment about its axis z through its origin O:
//   tau_ik = z . (n - r x f) = u_n' n + u_f' f,  u_n = z, u_f = r x z,  r = O - O_k,
// with z and r seen from link k. So each block of the regressor is a 6-vector times the link's
// wrench columns, written out below without forming them (Khalil and Dombre, ch. 9; the
// "projection" form of Atkeson, An and Hollerbach's regressor).
void chainRegressorInto(const ChainModel& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                        const Eigen::Ref<const Eigen::VectorXd>& qd, const Eigen::Ref<const Eigen::VectorXd>& qdd,
                        const ChainBaseMotion& base, ChainRegressorWorkspace& work, Eigen::Ref<Eigen::MatrixXd> out) {
  const int n = model.dof();
  requireSize("q", q.size(), n);
  requireSize("qd", qd.size(), n);
  requireSize("qdd", qdd.size(), n);
  const std::size_t un = static_cast<std::size_t>(n);
  work.axis_seen.resize(un);
  work.origin_seen.resize(un);
  work.link_column.resize(un);

  LinkMotion m{base.omega_radps, base.alpha_radps2, base.specific_force_mps2};
  const Eigen::Vector3d &w = m.w, &wd = m.wd, &a = m.a;
  int column = 0;
  for (int k = 0; k < n; ++k) {
    const std::size_t uk = static_cast<std::size_t>(k);
    const ChainJoint& j = model.joints[uk];
    const Eigen::Matrix3d R = advance(j, q[k], qd[k], qdd[k], m);  // link k's motion in its own frame
    const Eigen::Vector3d& p = j.parent_p_joint_m;
    // The joints below, seen from link k.
    for (int i = 0; i < k; ++i) {
      const std::size_t ui = static_cast<std::size_t>(i);
      work.axis_seen[ui] = R.transpose() * work.axis_seen[ui];
      work.origin_seen[ui] = R.transpose() * (work.origin_seen[ui] - p);
    }
    work.axis_seen[uk] = j.axis;
    work.origin_seen[uk].setZero();
    work.link_column[uk] = column;
    const double w_squared = w.squaredNorm();
    for (int i = 0; i <= k; ++i) {
      const std::size_t ui = static_cast<std::size_t>(i);
      const Eigen::Vector3d& un_ = work.axis_seen[ui];
      auto row = out.block<1, kLinkParams>(i, column);
      if (i == k) {  // its own joint: r = 0, so u_f = 0
        row[0] = 0.0;
        row.segment<3>(1) = a.cross(un_).transpose();
      } else {
        const Eigen::Vector3d uf = work.origin_seen[ui].cross(un_);
        row[0] = uf.dot(a);
        // u_f' ([wd]x + [w]x[w]x) - u_n' [a]x, as row vectors: (u_f x wd) + ((u_f x w) x w) + (a x u_n),
        // and ((u_f x w) x w) = (u_f . w) w - |w|^2 u_f.
        row.segment<3>(1) = (uf.cross(wd) + uf.dot(w) * w - w_squared * uf + a.cross(un_)).transpose();
      }
      // u_n' (L(wd) + [w]x L(w)) = u_n' L(wd) + (u_n x w)' L(w).
      row.segment<6>(4) = inertiaRow(un_, wd) + inertiaRow(un_.cross(w), w);
    }
    for (int i = k + 1; i < n; ++i) out.block<1, kLinkParams>(i, column).setZero();  // joints above carry nothing of it
    column += kLinkParams;
    const int own = (j.friction ? 2 : 0) + (j.armature ? 1 : 0);  // the joint's own columns: zero but on its row
    for (int i = 0; i < n; ++i) {
      for (int c = column; c < column + own; ++c) out(i, c) = 0.0;
    }
    if (j.friction) {
      out(k, column) = (qd[k] > 0.0) - (qd[k] < 0.0);
      out(k, column + 1) = qd[k];
      column += 2;
    }
    if (j.armature) out(k, column++) = qdd[k];
  }
}

// The same links' wrenches from phi itself: forward, each link's motion in its own frame (as the
// regressor's); its wrench about its origin, f = m a + wd x h + w x (w x h), n = I wd + w x (I w) +
// h x a (h = m c, I about the origin); backward, each link carries its children's, and its joint
// the moment about its axis, plus its own friction and armature.
void chainInverseDynamicsInto(const ChainModel& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                              const Eigen::Ref<const Eigen::VectorXd>& qd, const Eigen::Ref<const Eigen::VectorXd>& qdd,
                              const ChainBaseMotion& base, const Eigen::Ref<const Eigen::VectorXd>& phi, ChainRegressorWorkspace& work,
                              Eigen::Ref<Eigen::VectorXd> tau) {
  const int n = model.dof();
  requireSize("q", q.size(), n);
  requireSize("qd", qd.size(), n);
  requireSize("qdd", qdd.size(), n);
  if (phi.size() != model.standardParameterCount()) {
    throw std::invalid_argument("chain inverse dynamics: expected " + core::toText(model.standardParameterCount()) +
                                " standard parameters, got " + core::toText(static_cast<long long>(phi.size())));
  }
  const std::size_t un = static_cast<std::size_t>(n);
  work.R.resize(un);
  work.force.resize(un);
  work.moment.resize(un);
  const std::vector<JointParameterLayout> layout = model.layout();
  LinkMotion m{base.omega_radps, base.alpha_radps2, base.specific_force_mps2};
  const Eigen::Vector3d &w = m.w, &wd = m.wd, &a = m.a;
  for (int k = 0; k < n; ++k) {
    const std::size_t uk = static_cast<std::size_t>(k);
    work.R[uk] = advance(model.joints[uk], q[k], qd[k], qdd[k], m);
    const auto l = phi.segment<kLinkParams>(layout[uk].link);
    const Eigen::Vector3d h(l[1], l[2], l[3]);
    Eigen::Matrix3d I;
    I << l[4], l[5], l[6], l[5], l[7], l[8], l[6], l[8], l[9];
    work.force[uk] = l[0] * a + wd.cross(h) + w.cross(w.cross(h));
    work.moment[uk] = I * wd + w.cross(I * w) + h.cross(a);
  }
  for (int k = n - 1; k >= 0; --k) {
    const std::size_t uk = static_cast<std::size_t>(k);
    const ChainJoint& j = model.joints[uk];
    tau[k] = j.axis.dot(work.moment[uk]);
    if (j.friction) tau[k] += phi[layout[uk].friction] * static_cast<double>((qd[k] > 0.0) - (qd[k] < 0.0)) + phi[layout[uk].friction + 1] * qd[k];
    if (j.armature) tau[k] += phi[layout[uk].armature] * qdd[k];
    if (k > 0) {  // the parent carries this link's wrench, moved to its own origin and frame
      const Eigen::Vector3d f = work.R[uk] * work.force[uk];
      work.force[uk - 1] += f;
      work.moment[uk - 1] += work.R[uk] * work.moment[uk] + j.parent_p_joint_m.cross(f);
    }
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
