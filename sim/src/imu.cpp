#include "exoid/sim/imu.hpp"

#include <cmath>

namespace exoid::sim {

Eigen::Vector3d pedestalImuTruth(const mjModel* m, const mjData* d, const LegIndices& x) {
  const Eigen::Vector3d g(m->opt.gravity[0], m->opt.gravity[1], m->opt.gravity[2]);
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  double th = 0.0, thd = 0.0;
  if (x.hasMount()) {
    const Eigen::Vector3d r = Eigen::Vector3d::Map(d->site_xpos + 3 * x.site_imu) -
                              Eigen::Vector3d::Map(d->xpos + 3 * x.body_pedestal);
    th = d->qpos[x.mount_qadr[2]];
    thd = d->qvel[x.mount_vadr[2]];
    const double thdd = d->qacc[x.mount_vadr[2]];
    a << d->qacc[x.mount_vadr[0]], 0.0, d->qacc[x.mount_vadr[1]];
    a += thdd * Eigen::Vector3d(r.z(), 0.0, -r.x()) - thd * thd * Eigen::Vector3d(r.x(), 0.0, r.z());
  }
  const Eigen::Vector3d f = a - g;
  const double c = std::cos(th), s = std::sin(th);
  return {c * f.x() - s * f.z(), s * f.x() + c * f.z(), thd};
}

}  // namespace exoid::sim
