#include "exoid/ident/model/determination.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/signals/preprocess.hpp"

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace exoid::ident {

namespace {

// A joint moving less than this share of the record's widest joint motion is held (a lock's
// give, a held joint's tracking error): no dynamics is identified from it.
constexpr double kRelativeFloor = 1e-3;
// Frozen rows evaluated per record: a rank test, not a fit.
constexpr Eigen::Index kMaxSamplesPerRecord = 2000;
// Singular values below this share of the largest (column-scaled rows) are null directions, and a
// parameter is undetermined when a unit null direction has a component above kTouch along it.
constexpr double kRankTolerance = 1e-9;
constexpr double kTouch = 1e-3;

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// A signal's noise standard deviation from its second differences (white noise of variance s^2
// gives differences of variance 6 s^2; a smooth motion's are ~qdd dt^2), robustly (MAD).
double noiseOf(const Eigen::VectorXd& q) {
  std::vector<double> d2(static_cast<std::size_t>(q.size() - 2));
  for (Eigen::Index i = 0; i + 2 < q.size(); ++i) d2[static_cast<std::size_t>(i)] = q[i + 2] - 2.0 * q[i + 1] + q[i];
  const double m = median(d2);
  for (double& x : d2) x = std::abs(x - m);
  return 1.4826 * median(d2) / std::sqrt(6.0);
}

}  // namespace

bool RecordMotion::baseMoved() const {
  return std::any_of(base.begin(), base.end(), [](const SignalMotion& m) { return m.moved(); });
}

RecordMotion recordMotion(const Dataset& d) {
  const Eigen::Index n = d.size();
  if (n < 3) throw std::invalid_argument("motion of a record: expected at least 3 samples, got " + core::toText(n));
  // The range n samples of the noise alone span (the expected range of n normal draws is about
  // 2 sqrt(2 ln n) standard deviations), with 2 more for the spread of that range.
  const double noise_span = 2.0 * std::sqrt(2.0 * std::log(static_cast<double>(n))) + 2.0;
  const auto motion = [&](const std::string& name, const Eigen::VectorXd& x) {
    SignalMotion m;
    m.name = name;
    m.range = x.maxCoeff() - x.minCoeff();
    m.noise = noiseOf(x);
    m.floor = noise_span * m.noise;
    return m;
  };
  RecordMotion out;
  double widest = 0.0;
  for (Eigen::Index j = 0; j < d.dof(); ++j) {
    out.joints.push_back(motion(d.joints[static_cast<std::size_t>(j)], d.q_rad.col(j)));
    widest = std::max(widest, out.joints.back().range);
  }
  for (SignalMotion& m : out.joints) m.floor = std::max(m.floor, kRelativeFloor * widest);
  if (hasBaseColumns(d)) {
    for (const char* c : kBaseColumns) out.base.push_back(motion(c, d.extraColumn(c)));
  }
  return out;
}

Eigen::MatrixXd parameterDirections(const Robot& robot, const std::vector<int>& unknowns) {
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(robot.parameters(), static_cast<Eigen::Index>(unknowns.size()));
  for (std::size_t u = 0; u < unknowns.size(); ++u) d(unknowns[u], static_cast<Eigen::Index>(u)) = 1.0;
  return d;
}

Determination determination(const Robot& robot, const std::vector<Dataset>& records, const RecordRows& rows,
                            const std::vector<int>& unknowns, const std::vector<Eigen::Index>& equations) {
  return determination(robot, {DeterminationStage{&records, &rows, equations, parameterDirections(robot, unknowns)}});
}

namespace {

// One record's rows over `equations` (every parameter's column), at up to kMaxSamplesPerRecord of
// its samples, with every joint it held (and a still base) frozen.
Eigen::MatrixXd frozenRows(const Robot& robot, const RecordMotion& motion, const RecordRows& rows, Eigen::Index first_sample,
                           Eigen::Index samples, const std::vector<Eigen::Index>& equations, RobotWorkspace& work) {
  const Eigen::Index dof = robot.dof();
  JointSignals s;
  s.q_rad = rows.states.q_rad.middleRows(first_sample, samples);
  s.qd_radps = rows.states.qd_radps.middleRows(first_sample, samples);
  s.qdd_radps2 = rows.states.qdd_radps2.middleRows(first_sample, samples);
  if (rows.states.base.rows() > 0) s.base = rows.states.base.middleRows(first_sample, samples);
  s.t_s = rows.states.t_s.segment(first_sample, samples);
  s.tau_Nm = rows.states.tau_Nm.middleRows(first_sample, samples);
  for (Eigen::Index j = 0; j < dof; ++j) {
    if (motion.joints[static_cast<std::size_t>(j)].moved()) continue;
    s.q_rad.col(j).setConstant(s.q_rad.col(j).mean());
    s.qd_radps.col(j).setZero();
    s.qdd_radps2.col(j).setZero();
  }
  if (s.base.rows() > 0 && !motion.baseMoved()) {
    // Columns (f_x, f_z, omega, alpha): the mean specific force, no rotation.
    for (Eigen::Index c = 0; c < 2; ++c) s.base.col(c).setConstant(s.base.col(c).mean());
    s.base.rightCols(2).setZero();
  }
  const Eigen::Index step = std::max<Eigen::Index>(1, (samples + kMaxSamplesPerRecord - 1) / kMaxSamplesPerRecord);
  const Eigen::Index kept = (samples + step - 1) / step;
  const auto equation_count = static_cast<Eigen::Index>(equations.size());
  Eigen::MatrixXd block(kept * equation_count, robot.parameters());
  Eigen::MatrixXd Y(dof, robot.parameters());
  for (Eigen::Index k = 0; k < kept; ++k) {
    const Eigen::Index i = k * step;
    robotRowsInto(robot, s.q_rad.row(i).transpose(), s.qd_radps.row(i).transpose(), s.qdd_radps2.row(i).transpose(),
                  baseMotionAt(robot, s, i), work, Y);
    for (std::size_t e = 0; e < equations.size(); ++e) block.row(k * equation_count + static_cast<Eigen::Index>(e)) = Y.row(equations[e]);
  }
  return block;
}

// The columns of H (a stage's frozen rows times its directions) that no row determines: a zero
// column, or one a null direction of the column-scaled H touches.
std::vector<bool> undeterminedColumns(Eigen::MatrixXd H) {
  std::vector<bool> undetermined(static_cast<std::size_t>(H.cols()), false);
  for (Eigen::Index c = 0; c < H.cols(); ++c) {
    const double norm = H.col(c).norm();
    if (norm > 0.0) {
      H.col(c) /= norm;
    } else {
      undetermined[static_cast<std::size_t>(c)] = true;
    }
  }
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(H, Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();
  const double top = sv.size() ? sv[0] : 0.0;
  for (Eigen::Index k = 0; k < sv.size(); ++k) {
    if (sv[k] > kRankTolerance * top) continue;
    for (Eigen::Index c = 0; c < H.cols(); ++c) {
      if (std::abs(svd.matrixV()(c, k)) > kTouch) undetermined[static_cast<std::size_t>(c)] = true;
    }
  }
  return undetermined;
}

}  // namespace

Determination determination(const Robot& robot, const std::vector<DeterminationStage>& stages) {
  const Eigen::Index dof = robot.dof();
  Determination out;
  RobotWorkspace work;
  std::vector<bool> undetermined(static_cast<std::size_t>(robot.parameters()), false);
  for (const DeterminationStage& stage : stages) {
    const std::vector<Dataset>& records = *stage.records;
    const RecordRows& rows = *stage.rows;
    if (stage.directions.rows() != robot.parameters()) {
      throw std::invalid_argument("determination: a stage's directions have " + core::toText(stage.directions.rows()) + " rows, expected " +
                                  core::toText(robot.parameters()) + " (one per parameter)");
    }
    std::vector<Eigen::Index> equations = stage.equations;
    if (equations.empty()) {
      equations.resize(static_cast<std::size_t>(dof));
      std::iota(equations.begin(), equations.end(), Eigen::Index{0});
    }
    if (rows.dof != dof || rows.record_rows.size() != records.size()) {
      throw std::invalid_argument("determination: " + core::toText(records.size()) + " records but rows of " +
                                  core::toText(rows.record_rows.size()) + " records of a " + core::toText(rows.dof) + "-joint robot");
    }
    std::vector<Eigen::MatrixXd> blocks;
    Eigen::Index first_sample = 0, total = 0;
    for (std::size_t r = 0; r < records.size(); ++r) {
      out.records.push_back(recordMotion(records[r]));
      const Eigen::Index samples = rows.record_rows[r] / dof;
      blocks.push_back(frozenRows(robot, out.records.back(), rows, first_sample, samples, equations, work) * stage.directions);
      total += blocks.back().rows();
      first_sample += samples;
    }
    Eigen::MatrixXd H(total, stage.directions.cols());
    Eigen::Index at = 0;
    for (const Eigen::MatrixXd& b : blocks) {
      H.middleRows(at, b.rows()) = b;
      at += b.rows();
    }
    // A combination the stage's own motion leaves open leaves every parameter it carries open.
    const std::vector<bool> open = undeterminedColumns(std::move(H));
    for (Eigen::Index c = 0; c < stage.directions.cols(); ++c) {
      if (!open[static_cast<std::size_t>(c)]) continue;
      for (Eigen::Index i = 0; i < robot.parameters(); ++i) {
        if (std::abs(stage.directions(i, c)) > kTouch) undetermined[static_cast<std::size_t>(i)] = true;
      }
    }
  }
  for (std::size_t i = 0; i < undetermined.size(); ++i) {
    if (undetermined[i]) out.undetermined.push_back(static_cast<int>(i));
  }
  return out;
}

std::string Determination::describe(const Robot& robot) const {
  if (undetermined.empty()) return "";
  std::string s;
  for (std::size_t i = 0; i < undetermined.size(); ++i) s += (i ? ", " : "") + robot.names()[static_cast<std::size_t>(undetermined[i])];
  std::string held;
  const std::size_t joints = records.empty() ? 0 : records.front().joints.size();
  for (std::size_t j = 0; j < joints; ++j) {
    bool always = true;
    double range = 0.0, floor = 0.0;
    for (const RecordMotion& r : records) {
      always = always && !r.joints[j].moved();
      range = std::max(range, r.joints[j].range);
      floor = std::max(floor, r.joints[j].floor);
    }
    if (always) {
      held += std::string(held.empty() ? "" : "; ") + records.front().joints[j].name + " held in every record (range " +
              core::formatNumber(range, 3) + " rad, floor " + core::formatNumber(floor, 3) + " rad)";
    }
  }
  return s + (held.empty() ? std::string(" (no motion of the records separates them)") : " (" + held + ")");
}

}  // namespace exoid::ident
