#include "exoid/sim/truth.hpp"

#include "exoid/core/params.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace exoid::sim {

static_assert(kNumParams == core::kNumParams, "sim's truths are in core's parameter order");

// From the one table ident shares (core/params.hpp).
const std::array<const char*, kNumParams>& paramNames() {
  static const std::array<const char*, kNumParams> n = [] {
    std::array<const char*, kNumParams> out{};
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = core::kParams[i].name;
    return out;
  }();
  return n;
}
const std::array<const char*, kNumParams>& paramUnits() {
  static const std::array<const char*, kNumParams> u = [] {
    std::array<const char*, kNumParams> out{};
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = core::kParams[i].unit;
    return out;
  }();
  return u;
}

namespace {

struct Sums {
  double mass = 0, Mx = 0, My = 0, J = 0;
};

// Sums of `bodies` about the origin of `joint_body` (joints sit at body origins), in its frame.
Sums linkSums(const mjModel* m, const mjData* d, const std::vector<int>& bodies, int joint_body) {
  const mjtNum* R = d->xmat + 9 * joint_body;  // world <- body, row-major
  const mjtNum* o = d->xpos + 3 * joint_body;
  Sums s;
  for (int b : bodies) {
    const double mb = m->body_mass[b];
    mjtNum dw[3], dl[3];
    mju_sub3(dw, d->xipos + 3 * b, o);
    mju_mulMatTVec(dl, R, dw, 3, 3);  // R^T dw
    // Inertia in the joint body's frame: A = R^T Ri, I_l = A diag(I) A^T; yy = sum_k A_1k^2 I_k.
    const mjtNum* Ri = d->ximat + 9 * b;
    const mjtNum* I = m->body_inertia + 3 * b;
    double yy = 0;
    for (int k = 0; k < 3; ++k) {
      double a1k = 0;  // (R^T Ri)_{1k} = sum_r R_{r1} Ri_{rk}
      for (int r = 0; r < 3; ++r) a1k += R[3 * r + 1] * Ri[3 * r + k];
      yy += a1k * a1k * I[k];
    }
    s.mass += mb;
    s.Mx += mb * (-dl[2]);
    s.My += mb * (-dl[0]);
    s.J += yy + mb * (dl[0] * dl[0] + dl[2] * dl[2]);
  }
  return s;
}

// `shank` and every body below it reachable without a dof.
std::vector<int> weldedBelow(const mjModel* m, int root) {
  std::vector<int> out{root};
  for (int b = root + 1; b < m->nbody; ++b) {
    if (m->body_dofnum[b] != 0) continue;
    int p = m->body_parentid[b];
    while (p != root && p > 0 && m->body_dofnum[p] == 0) p = m->body_parentid[p];
    if (p == root) out.push_back(b);
  }
  return out;
}

struct Frame {
  double Lt = 0, g = 0;
};

Frame checkLeg(const LegModel& leg) {
  const mjModel* m = leg.model.get();
  const LegIndices& x = leg.idx;
  const std::string& src = leg.path;
  const mjtNum* k = m->body_pos + 3 * x.body_shank;
  if (std::abs(k[0]) > 1e-12) {
    throw std::invalid_argument("'" + src + "': the knee must lie on the thigh's -z axis (shank pos x = 0)");
  }
  if (m->opt.gravity[0] != 0 || m->opt.gravity[1] != 0 || !(m->opt.gravity[2] < 0)) {
    throw std::invalid_argument("'" + src + "': gravity must point along -z");
  }
  return {-k[2], -m->opt.gravity[2]};
}

ParamArray assemble(const LegModel& leg, const Sums& t, const Sums& s, double Lt) {
  const mjModel* m = leg.model.get();
  const LegIndices& x = leg.idx;
  ParamArray X{};
  X[5] = s.Mx;
  X[6] = s.My;
  X[7] = s.J;
  X[0] = t.Mx + s.mass * Lt;
  X[1] = t.My;
  X[2] = t.J + s.mass * Lt * Lt + s.J + m->dof_armature[x.vadr[0]];
  X[3] = leg.coulomb.fc_Nm[0];
  X[4] = m->dof_damping[x.vadr[0]];
  X[8] = leg.coulomb.fc_Nm[1];
  X[9] = m->dof_damping[x.vadr[1]];
  return X;
}

}  // namespace

Truth rigidTruth(const LegModel& leg) {
  const mjModel* m = leg.model.get();
  const LegIndices& x = leg.idx;
  const Frame f = checkLeg(leg);
  DataPtr d = makeData(m);
  mju_copy(d->qpos, m->qpos0, m->nq);
  mj_kinematics(m, d.get());
  const Sums t = linkSums(m, d.get(), {x.body_thigh}, x.body_thigh);
  const Sums s = linkSums(m, d.get(), weldedBelow(m, x.body_shank), x.body_shank);
  Truth tr;
  tr.x = assemble(leg, t, s, f.Lt);
  tr.thigh_length_m = f.Lt;
  tr.gravity_mps2 = f.g;
  tr.coulomb_v0_radps = leg.coulomb.v0_radps;
  tr.thigh_mass_kg = t.mass;
  tr.knee_armature_kgm2 = leg.model->dof_armature[leg.idx.vadr[1]];
  tr.shank_mass_kg = s.mass;
  tr.source = leg.path;
  return tr;
}

Truth truthFromModel(const std::string& path) { return rigidTruth(loadLeg(path, ModelVariant{}, true)); }

ParamArray lumpedParams(const LegModel& leg, const FourBar& fb, mjData* d, double q2) {
  const mjModel* m = leg.model.get();
  const LegIndices& x = leg.idx;
  const Frame f = checkLeg(leg);
  mju_copy(d->qpos, m->qpos0, m->nq);
  const FourBarState st = fb.closure(q2);
  d->qpos[x.qadr[1]] = q2;
  d->qpos[x.qadr_cyl] = st.cyl;
  d->qpos[x.qadr_rod] = st.rod;
  mj_kinematics(m, d);
  const Sums t = linkSums(m, d, {x.body_thigh, x.body_cylinder}, x.body_thigh);
  std::vector<int> shank = weldedBelow(m, x.body_shank);
  shank.push_back(x.body_rod);
  const Sums s = linkSums(m, d, shank, x.body_shank);
  return assemble(leg, t, s, f.Lt);
}

ParamBand lumpedBand(const LegModel& leg, double q2_min, double q2_max, int n) {
  if (n < 2 || !(q2_max >= q2_min)) {
    std::ostringstream ss;
    ss << "lumpedBand: need n >= 2 and q2_max >= q2_min, got n = " << n << ", [" << q2_min << ", " << q2_max << "]";
    throw std::invalid_argument(ss.str());
  }
  const FourBar fb(leg.model.get(), leg.idx);
  DataPtr d = makeData(leg.model.get());
  ParamBand band;
  band.q2_min_rad = q2_min;
  band.q2_max_rad = q2_max;
  band.samples = n;
  for (int i = 0; i < n; ++i) {
    const double q2 = q2_min + (q2_max - q2_min) * i / (n - 1);
    const ParamArray X = lumpedParams(leg, fb, d.get(), q2);
    for (int p = 0; p < kNumParams; ++p) {
      band.min[p] = i == 0 ? X[p] : std::min(band.min[p], X[p]);
      band.max[p] = i == 0 ? X[p] : std::max(band.max[p], X[p]);
    }
  }
  return band;
}

}  // namespace exoid::sim
