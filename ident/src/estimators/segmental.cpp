#include "exoid/ident/estimators/segmental.hpp"

#include "exoid/core/format.hpp"
#include "exoid/core/random.hpp"

#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace exoid::ident {
namespace {

// An orthonormal basis of the complement of span(V) in R^r (V: r x k, k <= r).
Eigen::MatrixXd complementOf(const Eigen::MatrixXd& V, Eigen::Index r) {
  if (V.cols() == 0) return Eigen::MatrixXd::Identity(r, r);
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(V);
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(r, r);
  return Q.rightCols(r - V.cols());
}

// A basis of span(D) (orthonormal columns): the parameters that lie in it as themselves first
// (the stage's unknowns are then whole parameters, as in the paper), the rest orthonormal.
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

// The parameter each column of B is, when every column is one (an axis); else empty.
std::vector<int> axesOf(const Eigen::MatrixXd& B) {
  std::vector<int> out;
  for (Eigen::Index c = 0; c < B.cols(); ++c) {
    Eigen::Index i = 0;
    const double largest = B.col(c).cwiseAbs().maxCoeff(&i);
    if (largest != 1.0 || B.col(c).squaredNorm() != 1.0) return {};
    out.push_back(static_cast<int>(i));
  }
  return out;
}

std::string describeDirection(const Eigen::VectorXd& d, const std::vector<std::string>& names) {
  std::ostringstream s;
  bool first = true;
  for (Eigen::Index i = 0; i < d.size(); ++i) {
    if (std::abs(d[i]) < 1e-6) continue;
    if (std::abs(d[i]) == 1.0 && d.squaredNorm() == 1.0) return (d[i] < 0 ? "-" : "") + names[static_cast<std::size_t>(i)];
    s << (first ? (d[i] < 0 ? "-" : "") : (d[i] < 0 ? " - " : " + "));
    s << core::formatNumber(std::abs(d[i]), 3) << " (" << names[static_cast<std::size_t>(i)] << ")";
    first = false;
  }
  return s.str();
}

std::string jointName(const Robot& robot, Eigen::Index j) { return robot.chain.joints[static_cast<std::size_t>(j)].name; }

}  // namespace

SegmentalPlan::SegmentalPlan(const Robot& robot, const std::vector<Eigen::Index>& first_joints, const BaseParameterOptions& structure)
    : robot_(robot), first_(first_joints) {
  structure.validate();
  if (first_.empty()) throw std::invalid_argument("segmental strategy: no stages");
  const Eigen::Index dof = robot.dof(), r = robot.parameters();
  for (std::size_t s = 0; s < first_.size(); ++s) {
    if (first_[s] < 0 || first_[s] >= dof) {
      throw std::invalid_argument("segmental strategy: stage " + core::toText(s + 1) + " starts at joint " + core::toText(first_[s]) +
                                  "; the robot has joints 0.." + core::toText(dof - 1));
    }
    if (s > 0 && first_[s] > first_[s - 1]) {
      throw std::invalid_argument("segmental strategy: stages go distal joints first (stage " + core::toText(s + 1) + " moves from joint " +
                                  core::toText(first_[s]) + ", below stage " + core::toText(s) + "'s joint " + core::toText(first_[s - 1]) + ")");
    }
  }
  Eigen::MatrixXd V(r, 0);  // the combinations of the stages so far (columns)
  for (std::size_t s = 0; s < first_.size(); ++s) {
    // What this stage determines: its locked-joint rows' directions outside span(V).
    const Eigen::MatrixXd N = complementOf(V, r);
    const Eigen::MatrixXd A = heldJointRows(robot, first_[s], structure) * N;
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinV);
    const Eigen::VectorXd& sv = svd.singularValues();
    Eigen::Index k = 0;
    while (k < sv.size() && sv[k] > structure.tolerance * sv[0]) ++k;
    if (sv.size() == 0 || !(sv[0] > 0.0) || k == 0) {
      throw std::invalid_argument("segmental strategy: stage " + core::toText(s + 1) + " (joints from " + jointName(robot, first_[s]) +
                                  " down) identifies no combination its earlier stages left open");
    }
    directions_.push_back(readableBasis(N * svd.matrixV().leftCols(k)));
    Eigen::MatrixXd V2(r, V.cols() + k);
    V2 << V, directions_.back();
    V = std::move(V2);
  }
  if (V.cols() < r) {
    const Eigen::MatrixXd open = complementOf(V, r);
    std::string names;
    for (Eigen::Index i = 0; i < open.cols(); ++i) names += (i ? "; " : "") + describeDirection(open.col(i), robot.names());
    throw std::invalid_argument("segmental strategy: the stages leave " + core::toText(open.cols()) + " combination(s) unidentified (" +
                                names + "): the last stage needs every joint moving (first joint 0)");
  }
}

Eigen::VectorXd StageProblem::theta(const Eigen::VectorXd& x) const {
  Eigen::VectorXd t = known;
  if (!parameters.empty()) {
    for (std::size_t i = 0; i < parameters.size(); ++i) t[parameters[i]] = x[static_cast<Eigen::Index>(i)];
  } else {
    t += directions * x;
  }
  return t;
}

StageProblem SegmentalPlan::problem(int s, const RecordRows& record, const std::vector<Eigen::VectorXd>& found) const {
  if (record.dof != robot_.dof() || record.W.cols() != robot_.parameters()) {
    throw std::invalid_argument("segmental strategy: stage " + core::toText(s + 1) + "'s record is not this robot's");
  }
  if (static_cast<int>(found.size()) != s) throw std::invalid_argument("segmental strategy: stage values out of order");
  StageProblem p;
  p.first_joint = first_[static_cast<std::size_t>(s)];
  p.directions = directions_[static_cast<std::size_t>(s)];
  p.parameters = axesOf(p.directions);
  for (Eigen::Index i = 0; i < p.directions.cols(); ++i) p.names.push_back(describeDirection(p.directions.col(i), robot_.names()));
  // The equations that involve the unknowns: a joint's equation whose columns are all structurally
  // zero along every direction carries nothing of them (the APAL leg's knee, in the hip stage).
  for (Eigen::Index k = 0; k < record.samples(); ++k) {
    for (Eigen::Index j = p.first_joint; j < record.dof; ++j) {
      bool involved = false;
      for (const int c : robot_.joint_columns[static_cast<std::size_t>(j)]) involved = involved || p.directions.row(c).any();
      if (involved) p.rows.push_back(k * record.dof + j);
    }
  }
  // What the earlier stages found, as parameters: whole ones assigned, combinations solved for.
  Eigen::MatrixXd V(robot_.parameters(), 0);
  Eigen::VectorXd c(0);
  for (int e = 0; e < s; ++e) {
    Eigen::MatrixXd V2(V.rows(), V.cols() + directions_[static_cast<std::size_t>(e)].cols());
    V2 << V, directions_[static_cast<std::size_t>(e)];
    V = std::move(V2);
    Eigen::VectorXd c2(c.size() + found[static_cast<std::size_t>(e)].size());
    c2 << c, found[static_cast<std::size_t>(e)];
    c = std::move(c2);
  }
  const std::vector<int> known_axes = axesOf(V);
  p.y = record.y(p.rows);
  if (V.cols() == 0) {
    p.known = Eigen::VectorXd::Zero(robot_.parameters());
  } else if (static_cast<Eigen::Index>(known_axes.size()) == V.cols()) {
    p.known = Eigen::VectorXd::Zero(robot_.parameters());
    for (std::size_t i = 0; i < known_axes.size(); ++i) p.known[known_axes[i]] = c[static_cast<Eigen::Index>(i)];
    const Eigen::MatrixXd known_columns = record.W(p.rows, known_axes);
    const Eigen::VectorXd known_torque = known_columns * c;  // evaluated apart, then subtracted: the paper's T1 - H_hip(6:10) X(6:10)
    p.y -= known_torque;
  } else {
    p.known = V.transpose().completeOrthogonalDecomposition().solve(c);
    p.y -= record.W(p.rows, Eigen::all) * p.known;
  }
  p.H = p.parameters.empty() ? Eigen::MatrixXd(record.W(p.rows, Eigen::all) * p.directions) : Eigen::MatrixXd(record.W(p.rows, p.parameters));
  return p;
}

Eigen::VectorXd SegmentalPlan::assemble(const std::vector<Eigen::VectorXd>& found) const {
  Eigen::MatrixXd V(robot_.parameters(), 0);
  Eigen::VectorXd c(0);
  for (std::size_t e = 0; e < found.size(); ++e) {
    Eigen::MatrixXd V2(V.rows(), V.cols() + directions_[e].cols());
    V2 << V, directions_[e];
    V = std::move(V2);
    Eigen::VectorXd c2(c.size() + found[e].size());
    c2 << c, found[e];
    c = std::move(c2);
  }
  const std::vector<int> axes = axesOf(V);
  if (static_cast<Eigen::Index>(axes.size()) == V.cols() && V.cols() == V.rows()) {
    Eigen::VectorXd theta(V.rows());
    for (std::size_t i = 0; i < axes.size(); ++i) theta[axes[i]] = c[static_cast<Eigen::Index>(i)];
    return theta;
  }
  return V.transpose().fullPivLu().solve(c);
}

bool SegmentalResult::usable() const {
  return std::all_of(stages.begin(), stages.end(), [](const StageResult& st) { return ident::usable(st.estimate.summary.status); });
}

SegmentalResult identifySegmental(const Robot& robot, const std::vector<SegmentalStage>& stages, Method method,
                                  const MethodOptions& options, const BaseParameterOptions& structure) {
  std::vector<Eigen::Index> first;
  for (const SegmentalStage& st : stages) first.push_back(st.first_joint);
  const SegmentalPlan plan(robot, first, structure);
  SegmentalResult out;
  std::vector<Eigen::VectorXd> found;
  for (int s = 0; s < plan.stages(); ++s) {
    StageResult res;
    res.problem = plan.problem(s, stages[static_cast<std::size_t>(s)].record, found);
    res.estimate = estimate(method, res.problem.H, res.problem.y, options);
    res.problem.H.resize(0, 0);
    res.problem.y.resize(0);
    found.push_back(res.estimate.x);
    out.stages.push_back(std::move(res));
  }
  out.theta = plan.assemble(found);
  return out;
}

}  // namespace exoid::ident
