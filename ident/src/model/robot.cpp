#include "exoid/ident/model/robot.hpp"

#include "exoid/core/format.hpp"
#include "exoid/core/parallel_for.hpp"
#include "exoid/core/random.hpp"
#include "exoid/ident/leg/params.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace exoid::ident {

Eigen::Index Robot::structuralColumnCount() const {
  Eigen::Index n = 0;
  for (const std::vector<int>& c : joint_columns) n += static_cast<Eigen::Index>(c.size());
  return n;
}

namespace {

// The kind of a standard parameter, by its name's suffix ("thigh.mx" -> a first moment).
ParameterKind standardKind(const std::string& name) {
  const std::string p = name.substr(name.rfind('.') + 1);
  if (p == "m") return ParameterKind::kMass;
  if (p == "mx" || p == "my" || p == "mz") return ParameterKind::kFirstMoment;
  if (p == "fc") return ParameterKind::kCoulomb;
  if (p == "fv") return ParameterKind::kViscous;
  if (p == "Ia") return ParameterKind::kArmature;
  return ParameterKind::kInertia;  // Ixx .. Izz
}

// The unit of a standard parameter, by its kind.
std::string standardUnit(const std::string& name) {
  switch (standardKind(name)) {
    case ParameterKind::kMass: return "kg";
    case ParameterKind::kFirstMoment: return "kg m";
    case ParameterKind::kCoulomb: return "N m";
    case ParameterKind::kViscous: return "N m s/rad";
    case ParameterKind::kInertia:
    case ParameterKind::kArmature: return "kg m^2";
  }
  return "kg m^2";
}

// Random states (and base motions) enough to find every column that is not zero by construction:
// an entry that is nonzero somewhere is nonzero at almost every state.
constexpr int kStructureStates = 8;

template <typename Rows>
std::vector<std::vector<int>> nonzeroColumns(int dof, int parameters, std::uint64_t seed, Rows&& rows) {
  core::Rng rng(seed);
  Eigen::MatrixXd seen = Eigen::MatrixXd::Zero(dof, parameters);
  Eigen::VectorXd q(dof), qd(dof), qdd(dof);
  for (int s = 0; s < kStructureStates; ++s) {
    for (int i = 0; i < dof; ++i) {
      q[i] = rng.uniform(-M_PI, M_PI);
      qd[i] = rng.uniform(-3.0, 3.0);
      qdd[i] = rng.uniform(-30.0, 30.0);
    }
    ChainBaseMotion base;
    for (int k = 0; k < 3; ++k) {
      base.specific_force_mps2[k] = rng.uniform(-10.0, 10.0);
      base.omega_radps[k] = rng.uniform(-1.0, 1.0);
      base.alpha_radps2[k] = rng.uniform(-10.0, 10.0);
    }
    seen = seen.cwiseMax(rows(q, qd, qdd, base).cwiseAbs());
  }
  std::vector<std::vector<int>> out(static_cast<std::size_t>(dof));
  for (int j = 0; j < dof; ++j) {
    for (int c = 0; c < parameters; ++c) {
      if (seen(j, c) > 0.0) out[static_cast<std::size_t>(j)].push_back(c);
    }
  }
  return out;
}

void requireRobotSize(const char* what, Eigen::Index got, int dof) {
  if (got != dof) {
    throw std::invalid_argument(std::string("robot regressor: expected ") + core::toText(dof) + " entries in " + what +
                                " (one per joint), got " + core::toText(static_cast<long long>(got)));
  }
}

BaseMotion planar(const ChainBaseMotion& b) {
  return {b.specific_force_mps2.x(), b.specific_force_mps2.z(), b.omega_radps.y(), b.alpha_radps2.y()};
}

// A chain robot's theta as standard parameters: its base parameters on their own (independent)
// columns, 0 elsewhere, so Y phi = Y_base theta.
const Eigen::VectorXd& standardOf(const Robot& robot, const Eigen::VectorXd& theta, Eigen::VectorXd& phi) {
  phi.setZero(robot.chain.standardParameterCount());
  for (int i = 0; i < robot.basis.rank; ++i) phi[robot.basis.independent[static_cast<std::size_t>(i)]] = theta[i];
  return phi;
}

}  // namespace

std::vector<ParameterKind> parameterKinds(const Robot& robot) {
  const std::vector<std::string> standard = robot.chain.standardParameterNames();
  std::vector<ParameterKind> out;
  for (int i = 0; i < robot.parameters(); ++i) {
    int lead = 0;
    if (!robot.basis.independent.empty()) {
      lead = robot.basis.independent[static_cast<std::size_t>(i)];
    } else {
      // A named basis: its row's first standard parameter.
      while (lead + 1 < robot.basis.combination.cols() && robot.basis.combination(i, lead) == 0.0) ++lead;
    }
    out.push_back(standardKind(standard[static_cast<std::size_t>(lead)]));
  }
  return out;
}

Robot chainRobot(const ChainModel& model, const BaseParameterOptions& options) {
  Robot r;
  r.chain = model;
  r.basis = baseParameters(model, options);
  const std::vector<std::string> standard = model.standardParameterNames();
  for (const int i : r.basis.independent) r.units.push_back(standardUnit(standard[static_cast<std::size_t>(i)]));
  for (const JointParameterLayout& l : model.layout()) {
    for (int i = 0; i < r.basis.rank; ++i) {
      if (l.friction >= 0 && r.basis.independent[static_cast<std::size_t>(i)] == l.friction) r.coulomb.push_back(i);
    }
  }
  RobotWorkspace work;
  r.joint_columns = nonzeroColumns(model.dof(), r.basis.rank, options.seed + 1, [&](const auto& q, const auto& qd, const auto& qdd,
                                                                                    const ChainBaseMotion& base) {
    Eigen::MatrixXd out(model.dof(), r.basis.rank);
    robotRowsInto(r, q, qd, qdd, base, work, out);
    return out;
  });
  return r;
}

ChainModel twoLinkChain(const LegConstants& c, bool knee_armature) {
  c.validate();
  ChainModel m;
  m.name = "2-link leg";
  ChainJoint hip;
  hip.name = "hip";
  hip.link = "thigh";
  hip.axis = Eigen::Vector3d::UnitY();
  ChainJoint knee = hip;
  knee.name = "knee";
  knee.link = "shank";
  knee.parent_p_joint_m = Eigen::Vector3d(0.0, 0.0, -c.thigh_length_m);
  knee.armature = knee_armature;
  m.joints = {hip, knee};
  m.gravity_mps2 = Eigen::Vector3d(0.0, 0.0, -c.gravity_mps2);
  return m;
}

Robot twoLinkLeg(const LegConstants& c, bool knee_armature) {
  Robot r;
  r.chain = twoLinkChain(c, knee_armature);
  r.two_link = c;
  r.knee_armature = knee_armature;
  const double Lt = c.thigh_length_m;
  // Standard layout: thigh 0 m, 1 mx, 2 my, 3 mz, 7 Iyy, 10 fc, 11 fv; the shank the same from 12;
  // knee.Ia 24 with the armature.
  const int p = kNumParams + (knee_armature ? 1 : 0);
  BaseParameters& b = r.basis;
  b.rank = p;
  b.combination = Eigen::MatrixXd::Zero(p, r.chain.standardParameterCount());
  Eigen::MatrixXd& G = b.combination;
  G(kMxt, 3) = -1.0, G(kMxt, 12) = Lt;
  G(kMyt, 1) = -1.0;
  G(kJt, 7) = 1.0, G(kJt, 12) = Lt * Lt, G(kJt, 19) = 1.0;
  G(kFc1, 10) = 1.0;
  G(kFv1, 11) = 1.0;
  G(kMxs, 15) = -1.0;
  G(kMys, 13) = -1.0;
  G(kJs, 19) = 1.0;
  G(kFc2, 22) = 1.0;
  G(kFv2, 23) = 1.0;
  if (knee_armature) G(kKneeArmature, 24) = 1.0;
  for (int i = 0; i < p; ++i) {
    b.names.emplace_back(paramName(i));
    b.combinations.emplace_back(paramName(i));
    r.units.emplace_back(i == kKneeArmature ? kneeArmatureInfo().unit : paramInfo()[static_cast<std::size_t>(i)].unit);
  }
  r.coulomb = {kFc1, kFc2};
  // The hip's equation has no knee friction (nor armature); the knee's no thigh parameter.
  r.joint_columns = {{kMxt, kMyt, kJt, kFc1, kFv1, kMxs, kMys, kJs}, {kMxs, kMys, kJs, kFc2, kFv2}};
  if (knee_armature) r.joint_columns[1].push_back(kKneeArmature);
  return r;
}

void robotRowsInto(const Robot& robot, const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& qd,
                   const Eigen::Ref<const Eigen::VectorXd>& qdd, const ChainBaseMotion& base, RobotWorkspace& work,
                   Eigen::Ref<Eigen::MatrixXd> out) {
  const int dof = robot.dof();
  requireRobotSize("q", q.size(), dof);
  requireRobotSize("qd", qd.size(), dof);
  requireRobotSize("qdd", qdd.size(), dof);
  if (robot.two_link) {
    RegressorRow hip, knee;
    regressorRows(*robot.two_link, q, qd, qdd, planar(base), hip, knee);
    out.row(0).head<kNumParams>() = hip;
    out.row(1).head<kNumParams>() = knee;
    if (robot.knee_armature) {
      out(0, kKneeArmature) = 0.0;
      out(1, kKneeArmature) = qdd[1];
    }
    return;
  }
  work.Y.resize(dof, robot.chain.standardParameterCount());
  chainRegressorInto(robot.chain, q, qd, qdd, base, work.chain, work.Y);
  for (int i = 0; i < robot.basis.rank; ++i) out.col(i) = work.Y.col(robot.basis.independent[static_cast<std::size_t>(i)]);
}

Eigen::VectorXd robotTorque(const Robot& robot, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                            const Eigen::VectorXd& theta, RobotWorkspace& work) {
  if (robot.two_link) {
    RegressorRow hip, knee;
    regressorRows(*robot.two_link, q, qd, qdd, hip, knee);
    const ParamVector x = theta.head<kNumParams>();  // a fixed-size copy: the dot products' summation order is X's
    const double ia2 = robot.knee_armature ? theta[kKneeArmature] : 0.0;
    return Eigen::Vector2d(hip.dot(x), knee.dot(x) + ia2 * qdd[1]);
  }
  Eigen::VectorXd tau(robot.dof());
  chainInverseDynamicsInto(robot.chain, q, qd, qdd, ChainBaseMotion::still(robot.chain), standardOf(robot, theta, work.phi), work.chain, tau);
  return tau;
}

ChainBaseMotion baseMotionAt(const Robot& robot, const JointSignals& s, Eigen::Index i) {
  if (s.base.rows() == 0) return ChainBaseMotion::still(robot.chain);
  ChainBaseMotion b;
  b.specific_force_mps2 = Eigen::Vector3d(s.base(i, 0), 0.0, s.base(i, 1));
  b.omega_radps = Eigen::Vector3d(0.0, s.base(i, 2), 0.0);
  b.alpha_radps2 = Eigen::Vector3d(0.0, s.base(i, 3), 0.0);
  return b;
}

void structuralColumns(const Robot& robot, const JointSignals& s, Eigen::Ref<Eigen::MatrixXd> out) {
  s.validate();
  const int dof = robot.dof();
  if (s.q_rad.cols() != dof) {
    throw std::invalid_argument("robot '" + robot.chain.name + "' has " + core::toText(dof) + " joints; the signals have " +
                                core::toText(s.q_rad.cols()));
  }
  if (out.rows() != s.size() || out.cols() != robot.structuralColumnCount()) {
    throw std::invalid_argument("structuralColumns: the output must be " + core::toText(s.size()) + " x " +
                                core::toText(robot.structuralColumnCount()));
  }
  if (robot.two_link) {  // the fast path: one pass of the hand-written regressor over the record
    constexpr int kColumns = kHipColumns + kNumParams - kKneeFirstColumn;
    nonzeroRegressorColumns(s, *robot.two_link, out.leftCols(kColumns));
    if (robot.knee_armature) out.col(kColumns) = s.qdd_radps2.col(1);
    return;
  }
  // A chain: each state's standard regressor, its structural entries (the standard column each
  // base parameter is) gathered into a row of a chunk of samples, the chunk copied into `out`
  // column by column (a row at a time would touch every column's cache line per sample).
  std::vector<Eigen::Index> gather;  // joint j's entry of standard column c at j + dof c (Y is column-major)
  for (int j = 0; j < dof; ++j) {
    for (const int c : robot.joint_columns[static_cast<std::size_t>(j)]) {
      gather.push_back(j + dof * static_cast<Eigen::Index>(robot.basis.independent[static_cast<std::size_t>(c)]));
    }
  }
  constexpr Eigen::Index kChunk = 256;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> chunk(kChunk, out.cols());
  Eigen::MatrixXd Y(dof, robot.chain.standardParameterCount());
  ChainRegressorWorkspace work;
  Eigen::VectorXd q(dof), qd(dof), qdd(dof);  // a row of a column-major matrix, copied once (a Ref to it would copy per call)
  for (Eigen::Index i0 = 0; i0 < s.size(); i0 += kChunk) {
    const Eigen::Index m = std::min(kChunk, s.size() - i0);
    for (Eigen::Index k = 0; k < m; ++k) {
      const Eigen::Index i = i0 + k;
      q = s.q_rad.row(i).transpose();
      qd = s.qd_radps.row(i).transpose();
      qdd = s.qdd_radps2.row(i).transpose();
      chainRegressorInto(robot.chain, q, qd, qdd, baseMotionAt(robot, s, i), work, Y);
      double* row = chunk.row(k).data();
      for (std::size_t g = 0; g < gather.size(); ++g) row[g] = Y.data()[gather[g]];
    }
    out.middleRows(i0, m) = chunk.topRows(m);
  }
}

Eigen::MatrixXd predictTorques(const Robot& robot, const JointSignals& s, const Eigen::VectorXd& theta, int threads) {
  if (theta.size() != robot.parameters()) {
    throw std::invalid_argument("predictTorques: expected " + core::toText(robot.parameters()) + " parameters, got " +
                                core::toText(theta.size()));
  }
  if (robot.two_link) {
    Eigen::MatrixXd tau = predictTorque(s, theta.head<kNumParams>(), *robot.two_link);
    if (robot.knee_armature) tau.col(1) += theta[kKneeArmature] * s.qdd_radps2.col(1);
    return tau;
  }
  s.validate();
  // A chain: its inverse dynamics at each state (Newton-Euler, O(dof)), in chunks of samples on
  // `threads` (each chunk alone: the same bytes whatever the number).
  Eigen::VectorXd phi_buffer;
  const Eigen::VectorXd phi = standardOf(robot, theta, phi_buffer);
  Eigen::MatrixXd tau(s.size(), robot.dof());
  constexpr Eigen::Index kChunk = 8192;
  const auto chunks = static_cast<std::size_t>((s.size() + kChunk - 1) / kChunk);
  core::parallelFor(chunks, threads, [&](std::size_t c) {
    ChainRegressorWorkspace work;
    Eigen::VectorXd row(robot.dof()), q(robot.dof()), qd(robot.dof()), qdd(robot.dof());
    const Eigen::Index from = static_cast<Eigen::Index>(c) * kChunk, to = std::min(s.size(), from + kChunk);
    for (Eigen::Index i = from; i < to; ++i) {
      q = s.q_rad.row(i).transpose();
      qd = s.qd_radps.row(i).transpose();
      qdd = s.qdd_radps2.row(i).transpose();
      chainInverseDynamicsInto(robot.chain, q, qd, qdd, baseMotionAt(robot, s, i), phi, work, row);
      tau.row(i) = row.transpose();
    }
  });
  return tau;
}

Eigen::MatrixXd heldJointRows(const Robot& robot, Eigen::Index first_moving, const BaseParameterOptions& o, const Eigen::VectorXd& held_at_rad) {
  const int n = robot.dof();
  if (first_moving < 0 || first_moving >= n) throw std::invalid_argument("heldJointRows: first_moving " + core::toText(first_moving) + " is not a joint");
  if (held_at_rad.size() != 0 && held_at_rad.size() != first_moving) {
    throw std::invalid_argument("heldJointRows: " + core::toText(held_at_rad.size()) + " held angles for " + core::toText(first_moving) + " held joints");
  }
  const Eigen::Index moving = n - first_moving;
  Eigen::MatrixXd W(static_cast<Eigen::Index>(o.samples) * moving, robot.parameters());
  core::Rng rng(core::deriveSeed(o.seed, static_cast<std::uint64_t>(first_moving)));
  RobotWorkspace work;
  Eigen::MatrixXd Y(n, robot.parameters());
  Eigen::VectorXd q(n), qd(n), qdd(n);
  for (int s = 0; s < o.samples; ++s) {
    for (int i = 0; i < n; ++i) {
      const bool held = i < first_moving;
      q[i] = held && held_at_rad.size() != 0 ? held_at_rad[i] : rng.uniform(-M_PI, M_PI);
      qd[i] = held ? 0.0 : rng.uniform(-3.0, 3.0);
      qdd[i] = held ? 0.0 : rng.uniform(-30.0, 30.0);
    }
    robotRowsInto(robot, q, qd, qdd, ChainBaseMotion::still(robot.chain), work, Y);
    W.middleRows(static_cast<Eigen::Index>(s) * moving, moving) = Y.bottomRows(moving);
  }
  return W;
}

}  // namespace exoid::ident
