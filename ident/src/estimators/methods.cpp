#include "exoid/ident/estimators/methods.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/estimators/lad_box.hpp"

#include <cmath>
#include <stdexcept>

namespace exoid::ident {

const char* toString(Method m) {
  switch (m) {
    case Method::kLs: return "ls";
    case Method::kRls: return "rls";
    case Method::kPso: return "pso";
    case Method::kRlsPso: return "rls-pso";
    case Method::kLad: return "lad";
    case Method::kIdimIv: return "idim-iv";
    case Method::kIvBand: return "iv-band";
  }
  return "unknown";
}

const std::vector<Method>& allMethods() {
  static const std::vector<Method> all = {Method::kLs, Method::kRls, Method::kPso, Method::kRlsPso,
                                          Method::kLad};
  return all;
}

Method parseMethod(const std::string& name) {
  for (Method m : allMethods()) {
    if (name == toString(m)) return m;
  }
  if (name == toString(Method::kIdimIv)) return Method::kIdimIv;
  if (name == toString(Method::kIvBand)) return Method::kIvBand;
  throw std::invalid_argument("unknown method '" + name + "' (expected ls, rls, pso, rls-pso, lad, idim-iv or iv-band; "
                              "the command line also takes all = every method but idim-iv and iv-band)");
}

void MethodOptions::validate() const {
  ls.validate();
  rls_pso.rls.validate();
  rls_pso.range.validate();
  rls_pso.pso.validate();
  lad.validate();
  if (!(wide_box_half_width > 0.0 && std::isfinite(wide_box_half_width))) {
    throw std::invalid_argument("'wide_box_half_width' must be > 0, got " +
                                core::toText(wide_box_half_width));
  }
}

double psoHalfWidthFromLs(const Eigen::VectorXd& ls_estimate) {
  if (ls_estimate.size() == 0 || !ls_estimate.allFinite()) {
    throw std::invalid_argument("cannot size the PSO box from the data (no usable LS estimate); give --wide-box");
  }
  return 10.0 * std::max(ls_estimate.cwiseAbs().maxCoeff(), 1e-6);
}

namespace {
// The regressor's conditioning limits every estimator alike (a search does not add information):
// a usable estimate from an ill-conditioned regressor becomes kIllConditioned.
void holdToConditionBound(Estimate& e, const Eigen::MatrixXd& H, double max_condition) {
  if (!e.condition_number) e.condition_number = scaledConditionNumber(H);
  if (!usable(e.summary.status) || !(*e.condition_number > max_condition)) return;
  e.summary.message = illConditionedMessage(*e.condition_number, max_condition) + " (the method itself: " +
                      toString(e.summary.status) + ", " + e.summary.message + ")";
  e.summary.status = Status::kIllConditioned;
}

void fromPso(Estimate& e, PsoResult&& pso) {
  e.x = std::move(pso.x);
  e.summary = pso.summary;
  e.cost_history = std::move(pso.best_cost_history);
}
}  // namespace

Estimate estimate(Method method, const Eigen::MatrixXd& H, const Eigen::VectorXd& y,
                  const MethodOptions& o) {
  o.validate();
  if (method == Method::kIdimIv) {
    throw std::invalid_argument("idim-iv is not a method over y = H x alone: it simulates the model under the "
                                "record's controller (identifySegmentalIv, identifyAllIv)");
  }
  if (method == Method::kIvBand) {
    throw std::invalid_argument("iv-band is not a method over y = H x alone: its instruments come from the records "
                                "(band_iv.hpp, identifyBandIv)");
  }
  Estimate e;
  e.method = method;
  std::optional<LadResult> lad;
  if (method == Method::kLad || (o.report_optimality_gap && (method == Method::kPso || method == Method::kRlsPso))) {
    lad = solveLeastAbsoluteDeviations(H, y, o.lad);
  }
  switch (method) {
    case Method::kLs: {
      LsResult ls = solveLeastSquares(H, y, o.ls);
      e.x = ls.x;
      e.summary = ls.summary;
      e.rank = ls.rank;
      e.condition_number = ls.condition_number;
      e.unidentifiable = ls.unidentifiable;
      e.collinearity_r2 = ls.collinearity_r2;
      break;
    }
    case Method::kRls: {
      RlsResult rls = runRls(H, y, o.rls_pso.rls);
      e.box = fluctuationRange(rls.history, o.rls_pso.range);
      e.x = rls.x;
      e.summary = rls.summary;
      break;
    }
    case Method::kPso: {
      const Box box = Box::uniform(H.cols(), -o.wide_box_half_width, o.wide_box_half_width);
      e.box = box;
      fromPso(e, identifyPso(H, y, box, o.rls_pso.pso, o.rls_pso.cost));
      break;
    }
    case Method::kRlsPso: {
      RlsPsoResult r = identifyRlsPso(H, y, o.rls_pso);
      e.box = r.box;
      fromPso(e, std::move(r.pso));
      e.summary.wall_time_s += r.rls.summary.wall_time_s;
      break;
    }
    case Method::kLad:
      e.x = lad->x;
      e.summary = lad->summary;
      break;
    case Method::kIdimIv:
    case Method::kIvBand: break;  // rejected above
  }
  holdToConditionBound(e, H, o.ls.max_condition);
  e.l1_cost = (y - H * e.x).cwiseAbs().sum();
  const auto gap = [&](double optimum) { return optimum > 0.0 ? (e.l1_cost - optimum) / optimum : 0.0; };
  if (lad && usable(lad->summary.status)) {
    e.optimum_l1_cost = lad->cost;
    e.optimality_gap_rel = gap(lad->cost);
  }
  if (o.report_optimality_gap && e.box && (method == Method::kPso || method == Method::kRlsPso)) {
    const BoxedLadResult boxed = solveBoxedLeastAbsoluteDeviations(H, y, *e.box, o.lad);
    if (usable(boxed.summary.status)) {
      e.optimum_box_l1_cost = boxed.cost;
      e.optimality_gap_box_rel = gap(boxed.cost);
    }
  }
  return e;
}

}  // namespace exoid::ident
