#include "exoid/sim/four_bar.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace exoid::sim {
namespace {

bool isIdentityQuat(const mjtNum* q) {
  return std::abs(q[0] - 1) < 1e-12 && std::abs(q[1]) < 1e-12 && std::abs(q[2]) < 1e-12 &&
         std::abs(q[3]) < 1e-12;
}
bool isYAxis(const mjtNum* a) {
  return std::abs(a[0]) < 1e-12 && std::abs(a[1] - 1) < 1e-12 && std::abs(a[2]) < 1e-12;
}
double psi(double x, double z) { return std::atan2(x, z); }

}  // namespace

FourBar::FourBar(const mjModel* m, const LegIndices& x) {
  auto fail = [](const std::string& what) {
    throw std::invalid_argument("four-bar geometry: " + what);
  };
  for (int b : {x.body_thigh, x.body_shank, x.body_cylinder, x.body_rod}) {
    if (!isIdentityQuat(m->body_quat + 4 * b)) fail("bodies thigh, shank, cylinder, rod must not be rotated at q = 0");
  }
  for (int j : {x.jnt[0], x.jnt[1], x.jnt_cyl}) {
    if (!isYAxis(m->jnt_axis + 3 * j)) fail("hip, knee and cylinder_hinge axes must be 0 1 0");
    const mjtNum* p = m->jnt_pos + 3 * j;
    if (std::abs(p[0]) > 1e-12 || std::abs(p[1]) > 1e-12 || std::abs(p[2]) > 1e-12) fail("joints must sit at their body origin");
  }
  for (int j = 0; j < m->njnt; ++j) {
    if (m->qpos0[m->jnt_qposadr[j]] != 0.0 && m->jnt_type[j] != mjJNT_FREE && m->jnt_type[j] != mjJNT_BALL)
      fail("joint refs must be 0 (qpos0 = 0)");
  }
  if (m->body_parentid[x.body_cylinder] != x.body_thigh || m->body_parentid[x.body_shank] != x.body_thigh ||
      m->body_parentid[x.body_rod] != x.body_cylinder) {
    fail("expected cylinder and shank children of thigh, rod child of cylinder");
  }
  const mjtNum* c = m->body_pos + 3 * x.body_cylinder;
  const mjtNum* k = m->body_pos + 3 * x.body_shank;
  const mjtNum* rp = m->body_pos + 3 * x.body_rod;
  const mjtNum* a1 = m->eq_data + mjNEQDATA * x.eq_loop;      // rod frame
  const mjtNum* a2 = a1 + 3;                                   // shank frame
  cx_ = c[0];
  cz_ = c[2];
  kx_ = k[0];
  kz_ = k[2];
  dx_ = a2[0];
  dz_ = a2[2];
  const double px = rp[0] + a1[0], py = rp[1] + a1[1], pz = rp[2] + a1[2];
  // Planarity: rod end and shank anchor in the same sagittal plane.
  const double y_rod = c[1] + py, y_shank = k[1] + a2[1];
  if (std::abs(y_rod - y_shank) > 1e-9) fail("rod end and shank anchor differ in y");
  const mjtNum* u = m->jnt_axis + 3 * x.jnt_rod;
  p_len_ = std::sqrt(px * px + pz * pz);
  const double cross = px * u[2] - pz * u[0];
  const double dot = px * u[0] + pz * u[2];
  if (std::abs(u[1]) > 1e-12 || std::abs(cross) > 1e-9 * p_len_ || dot <= 0) {
    fail("the rod end must lie on the rod_slide axis, away from the cylinder hinge");
  }
  p_psi_ = psi(px, pz);
  const double r0x = kx_ + dx_ - cx_, r0z = kz_ + dz_ - cz_;
  const double gap = std::hypot(r0x - px, r0z - pz);
  if (gap > 1e-9) {
    std::ostringstream ss;
    ss << "the loop is not assembled at qpos = 0 (rod end and shank anchor " << gap << " m apart)";
    fail(ss.str());
  }
}

FourBarState FourBar::closure(double q2) const {
  const double s = std::sin(q2), co = std::cos(q2);
  // D relative to the knee, rotated by q2 about +y: (x, z) -> (x c + z s, -x s + z c).
  const double ex = dx_ * co + dz_ * s, ez = -dx_ * s + dz_ * co;
  const double rx = kx_ + ex - cx_, rz = kz_ + ez - cz_;
  const double rx1 = ez, rz1 = -ex;    // d/dq2
  const double rx2 = -ex, rz2 = -ez;   // d^2/dq2^2
  const double l2 = rx * rx + rz * rz, l = std::sqrt(l2);
  FourBarState st;
  double dpsi = psi(rx, rz) - p_psi_;
  if (dpsi > M_PI) dpsi -= 2 * M_PI;
  if (dpsi < -M_PI) dpsi += 2 * M_PI;
  st.cyl = dpsi;
  st.rod = l - p_len_;
  const double n = rz * rx1 - rx * rz1;          // l^2 dpsi/dq2
  const double n1 = rz * rx2 - rx * rz2;
  const double l1 = (rx * rx1 + rz * rz1) / l;
  st.dcyl = n / l2;
  st.drod = l1;
  st.ddcyl = n1 / l2 - 2 * n * l1 / (l2 * l);
  st.ddrod = (rx1 * rx1 + rz1 * rz1 + rx * rx2 + rz * rz2) / l - l1 * l1 / l;
  return st;
}

void setLegState(const mjModel* m, mjData* d, const LegIndices& x, const FourBar& fb,
                 const std::array<double, 2>& q, const std::array<double, 2>& qd,
                 const std::array<double, 2>* qdd) {
  (void)m;
  for (int j = 0; j < 2; ++j) {
    d->qpos[x.qadr[j]] = q[j];
    d->qvel[x.vadr[j]] = qd[j];
  }
  const FourBarState st = fb.closure(q[1]);
  d->qpos[x.qadr_cyl] = st.cyl;
  d->qpos[x.qadr_rod] = st.rod;
  d->qvel[x.vadr_cyl] = st.dcyl * qd[1];
  d->qvel[x.vadr_rod] = st.drod * qd[1];
  if (qdd) {
    const std::array<double, 2>& a = *qdd;
    d->qacc[x.vadr[0]] = a[0];
    d->qacc[x.vadr[1]] = a[1];
    d->qacc[x.vadr_cyl] = st.dcyl * a[1] + st.ddcyl * qd[1] * qd[1];
    d->qacc[x.vadr_rod] = st.drod * a[1] + st.ddrod * qd[1] * qd[1];
  }
}

double loopError(const mjModel* m, const mjData* d, const LegIndices& x) {
  if (x.eq_loop < 0) return 0.0;
  const mjtNum* a1 = m->eq_data + mjNEQDATA * x.eq_loop;
  const mjtNum* a2 = a1 + 3;
  const int b1 = m->eq_obj1id[x.eq_loop], b2 = m->eq_obj2id[x.eq_loop];
  mjtNum p1[3], p2[3];
  mju_rotVecMat(p1, a1, d->xmat + 9 * b1);
  mju_rotVecMat(p2, a2, d->xmat + 9 * b2);
  double e2 = 0;
  for (int i = 0; i < 3; ++i) {
    const double e = (d->xpos[3 * b1 + i] + p1[i]) - (d->xpos[3 * b2 + i] + p2[i]);
    e2 += e * e;
  }
  return std::sqrt(e2);
}

}  // namespace exoid::sim
