#include "exoid/ident/model/chain_segmental.hpp"

#include "exoid/core/format.hpp"
#include "exoid/core/random.hpp"
#include "exoid/ident/model/chain_regressor.hpp"

#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace exoid::ident {
namespace {

// The stage's base regressor at random states, the locked joints still (the structure, not data).
Eigen::MatrixXd lockedRegressor(const ChainModel& model, const BaseParameters& base, Eigen::Index first,
                                const BaseParameterOptions& o) {
  const int n = model.dof();
  const Eigen::Index moving = n - first;
  Eigen::MatrixXd W(static_cast<Eigen::Index>(o.samples) * moving, model.standardParameterCount());
  core::Rng rng(core::deriveSeed(o.seed, static_cast<std::uint64_t>(first)));
  ChainRegressorWorkspace work;
  Eigen::MatrixXd Y(n, model.standardParameterCount());
  Eigen::VectorXd q(n), qd(n), qdd(n);
  for (int s = 0; s < o.samples; ++s) {
    for (int i = 0; i < n; ++i) {
      q[i] = rng.uniform(-M_PI, M_PI);
      qd[i] = i < first ? 0.0 : rng.uniform(-3.0, 3.0);
      qdd[i] = i < first ? 0.0 : rng.uniform(-30.0, 30.0);
    }
    chainRegressorInto(model, q, qd, qdd, ChainBaseMotion::still(model), work, Y);
    W.middleRows(static_cast<Eigen::Index>(s) * moving, moving) = Y.bottomRows(moving);
  }
  return base.baseRegressor(W);
}

// An orthonormal basis of the complement of span(V) in R^r (V: r x k, k <= r).
Eigen::MatrixXd complementOf(const Eigen::MatrixXd& V, Eigen::Index r) {
  if (V.cols() == 0) return Eigen::MatrixXd::Identity(r, r);
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(V);
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(r, r);
  return Q.rightCols(r - V.cols());
}

// A basis of span(D) (orthonormal columns): the base parameters that lie in it as themselves
// first (the stage's unknowns are then whole parameters, as in the paper), the rest orthonormal.
Eigen::MatrixXd readableBasis(const Eigen::MatrixXd& D) {
  const Eigen::Index r = D.rows(), k = D.cols();
  std::vector<Eigen::Index> axes;
  for (Eigen::Index i = 0; i < r && static_cast<Eigen::Index>(axes.size()) < k; ++i) {
    if (D.row(i).squaredNorm() > 1.0 - 1e-9) axes.push_back(i);  // e_i lies in span(D)
  }
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(r, k);
  for (std::size_t a = 0; a < axes.size(); ++a) B(axes[a], static_cast<Eigen::Index>(a)) = 1.0;
  const auto na = static_cast<Eigen::Index>(axes.size());
  if (na < k) {
    Eigen::MatrixXd rest = D;  // D less its components along the axes, orthonormalised
    for (Eigen::Index a = 0; a < na; ++a) rest -= B.col(a) * (B.col(a).transpose() * rest);
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(rest, Eigen::ComputeThinU);
    B.rightCols(k - na) = svd.matrixU().leftCols(k - na);
  }
  return B;
}

std::string describeDirection(const Eigen::VectorXd& d, const std::vector<std::string>& names) {
  std::ostringstream s;
  bool first = true;
  for (Eigen::Index i = 0; i < d.size(); ++i) {
    if (std::abs(d[i]) < 1e-6) continue;
    const bool unit = std::abs(std::abs(d[i]) - 1.0) < 1e-9;
    s << (first ? (d[i] < 0 ? "-" : "") : (d[i] < 0 ? " - " : " + "));
    if (!unit) s << core::formatNumber(std::abs(d[i]), 3) << " ";
    s << "(" << names[static_cast<std::size_t>(i)] << ")";
    first = false;
  }
  return s.str();
}

}  // namespace

ChainSegmentalResult identifyChainSegmental(const ChainModel& model, const BaseParameters& base,
                                            const std::vector<ChainStage>& stages, Method method,
                                            const MethodOptions& options, const BaseParameterOptions& structure) {
  structure.validate();
  if (stages.empty()) throw std::invalid_argument("segmental strategy: no stages");
  const Eigen::Index dof = model.dof(), r = base.rank;
  for (std::size_t s = 0; s < stages.size(); ++s) {
    const ChainStage& st = stages[s];
    if (st.first_joint < 0 || st.first_joint >= dof) {
      throw std::invalid_argument("segmental strategy: stage " + core::toText(s + 1) + " starts at joint " +
                                  core::toText(st.first_joint) + "; the model has joints 0.." + core::toText(dof - 1));
    }
    if (s > 0 && st.first_joint > stages[s - 1].first_joint) {
      throw std::invalid_argument("segmental strategy: stages go distal joints first (stage " + core::toText(s + 1) +
                                  " moves from joint " + core::toText(st.first_joint) + ", below stage " +
                                  core::toText(s) + "'s joint " + core::toText(stages[s - 1].first_joint) + ")");
    }
    if (st.record.dof != dof || st.record.W.cols() != model.standardParameterCount()) {
      throw std::invalid_argument("segmental strategy: stage " + core::toText(s + 1) + "'s record is not this model's");
    }
  }
  ChainSegmentalResult out;
  Eigen::MatrixXd V(r, 0);   // the combinations known so far (columns)
  Eigen::VectorXd c(0);      // and their values: V' beta = c
  for (std::size_t s = 0; s < stages.size(); ++s) {
    const ChainStage& st = stages[s];
    const std::string joint = model.joints[static_cast<std::size_t>(st.first_joint)].name;
    // What this stage determines: its locked-joint rows' directions outside span(V).
    const Eigen::MatrixXd N = complementOf(V, r);
    const Eigen::MatrixXd A = lockedRegressor(model, base, st.first_joint, structure) * N;
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinV);
    const Eigen::VectorXd& sv = svd.singularValues();
    Eigen::Index k = 0;
    while (k < sv.size() && sv[k] > structure.tolerance * sv[0]) ++k;
    if (sv.size() == 0 || !(sv[0] > 0.0) || k == 0) {
      throw std::invalid_argument("segmental strategy: stage " + core::toText(s + 1) + " (joints from " + joint +
                                  " down) identifies no combination its earlier stages left open");
    }
    const Eigen::MatrixXd B = readableBasis(N * svd.matrixV().leftCols(k));
    // The data: the stage's rows, what is known moved to the torque side.
    const std::vector<Eigen::Index> rows = st.record.rowsOfJointsFrom(st.first_joint);
    const Eigen::MatrixXd Yb = base.baseRegressor(st.record.W(rows, Eigen::all));
    Eigen::VectorXd y = st.record.y(rows);
    if (V.cols() > 0) y -= Yb * V.transpose().completeOrthogonalDecomposition().solve(c);
    ChainStageResult res;
    res.first_joint = st.first_joint;
    res.rows = static_cast<Eigen::Index>(rows.size());
    res.directions = B;
    for (Eigen::Index i = 0; i < k; ++i) res.names.push_back(describeDirection(B.col(i), base.names));
    res.estimate = estimate(method, Yb * B, y, options);
    Eigen::MatrixXd V2(r, V.cols() + k);
    V2 << V, B;
    Eigen::VectorXd c2(c.size() + k);
    c2 << c, res.estimate.x;
    V = std::move(V2);
    c = std::move(c2);
    out.stages.push_back(std::move(res));
  }
  if (V.cols() < r) {
    const Eigen::MatrixXd open = complementOf(V, r);
    std::string names;
    for (Eigen::Index i = 0; i < open.cols(); ++i) names += (i ? "; " : "") + describeDirection(open.col(i), base.names);
    throw std::invalid_argument("segmental strategy: the stages leave " + core::toText(open.cols()) +
                                " combination(s) unidentified (" + names +
                                "): the last stage needs every joint moving (first joint 0)");
  }
  out.beta = V.transpose().fullPivLu().solve(c);
  return out;
}

}  // namespace exoid::ident
