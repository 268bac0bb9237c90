#include "exoid/sim/inverse_dynamics.hpp"

namespace exoid::sim {

IdealInverseDynamics::IdealInverseDynamics(LegModel leg)
    : leg_(std::move(leg)), data_(makeData(leg_.model.get())), fb_(leg_.model.get(), leg_.idx) {
  mjModel* m = leg_.model.get();
  // The loop is handled by the closure map, the hip lock is a torque we want to see.
  m->eq_active[leg_.idx.eq_loop] = 0;
  m->eq_active[leg_.idx.eq_hip_lock] = 0;
  passive_massless_ = leg_.kinematic_loop;
  mju_zero(data_->qpos, m->nq);
  mju_zero(data_->qvel, m->nv);
  mju_zero(data_->qacc, m->nv);
}

Eigen::Vector2d IdealInverseDynamics::torque(const Eigen::Vector2d& q, const Eigen::Vector2d& qd,
                                             const Eigen::Vector2d& qdd) {
  const mjModel* m = leg_.model.get();
  mjData* d = data_.get();
  const LegIndices& x = leg_.idx;
  const std::array<double, 2> a = {qdd[0], qdd[1]};
  setLegState(m, d, x, fb_, {q[0], q[1]}, {qd[0], qd[1]}, &a);
  mj_inverse(m, d);
  Eigen::Vector2d tau(d->qfrc_inverse[x.vadr[0]], d->qfrc_inverse[x.vadr[1]]);
  if (!passive_massless_) {
    const FourBarState st = fb_.closure(q[1]);
    tau[1] += st.dcyl * d->qfrc_inverse[x.vadr_cyl] + st.drod * d->qfrc_inverse[x.vadr_rod];
  }
  tau[0] += leg_.coulomb.torque(0, qd[0]);
  tau[1] += leg_.coulomb.torque(1, qd[1]);
  return tau;
}

}  // namespace exoid::sim
