#include "exoid/ident/estimators/rls_pso.hpp"

namespace exoid::ident {

PsoResult identifyPso(const Eigen::MatrixXd& H, const Eigen::VectorXd& y, const Box& box,
                      const PsoOptions& options, CostNorm norm) {
  const LinearResidualCost cost(H, y, norm);
  return minimizePso(
      [&cost](const Eigen::Ref<const Eigen::MatrixXd>& particles, Eigen::Ref<Eigen::VectorXd> f) {
        cost.evaluate(particles, f);
      },
      box, options);
}

RlsPsoResult identifyRlsPso(const Eigen::MatrixXd& H, const Eigen::VectorXd& y,
                            const RlsPsoOptions& options) {
  RlsPsoResult r;
  r.rls = runRls(H, y, options.rls);
  r.box = fluctuationRange(r.rls.history, options.range);
  r.pso = identifyPso(H, y, r.box, options.pso, options.cost);
  return r;
}

}  // namespace exoid::ident
