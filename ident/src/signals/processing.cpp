#include "exoid/ident/signals/processing.hpp"

#include "exoid/core/format.hpp"
#include "exoid/core/parallel_for.hpp"
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/signals/base_terms.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <utility>

namespace exoid::ident {

std::vector<Eigen::Index> RecordRows::rowsOfJoint(Eigen::Index j) const {
  std::vector<Eigen::Index> rows(static_cast<std::size_t>(samples()));
  for (Eigen::Index k = 0; k < samples(); ++k) rows[static_cast<std::size_t>(k)] = k * dof + j;
  return rows;
}

std::vector<Eigen::Index> RecordRows::rowsOfJointsFrom(Eigen::Index first) const {
  std::vector<Eigen::Index> rows;
  rows.reserve(static_cast<std::size_t>(samples() * std::max<Eigen::Index>(0, dof - first)));
  for (Eigen::Index k = 0; k < samples(); ++k) {
    for (Eigen::Index j = first; j < dof; ++j) rows.push_back(k * dof + j);
  }
  return rows;
}

Eigen::MatrixXd RecordRows::jointW(Eigen::Index j) const { return W(rowsOfJoint(j), Eigen::all); }

Eigen::VectorXd RecordRows::jointY(Eigen::Index j) const { return y(rowsOfJoint(j)); }

namespace {

// The columns a block of block_samples rows is sized for: up to 32 (the 2-link leg has 15, 16 with
// its knee armature); a robot with more gets proportionally fewer rows a block.
constexpr Eigen::Index kBlockColumns = 32;

void checkJoints(const Robot& robot, const JointSignals& s) {
  s.validate();
  if (s.q_rad.cols() != robot.dof()) {
    throw std::invalid_argument("robot '" + robot.chain.name + "' has " + core::toText(robot.dof()) + " joints; the signals have " +
                                core::toText(s.q_rad.cols()));
  }
}

// States at local rows first, first + r, ... <= last of s (m of them).
JointSignals keptStates(const JointSignals& s, Eigen::Index first, Eigen::Index m, int r) {
  JointSignals out;
  const Eigen::Index dof = s.q_rad.cols();
  out.t_s.resize(m);
  out.q_rad.resize(m, dof);
  out.qd_radps.resize(m, dof);
  out.qdd_radps2.resize(m, dof);
  out.tau_Nm.resize(m, dof);
  if (s.base.rows() > 0) out.base.resize(m, 4);
  for (Eigen::Index k = 0; k < m; ++k) {
    const Eigen::Index i = first + k * r;
    out.t_s[k] = s.t_s[i];
    out.q_rad.row(k) = s.q_rad.row(i);
    out.qd_radps.row(k) = s.qd_radps.row(i);
    out.qdd_radps2.row(k) = s.qdd_radps2.row(i);
    if (s.base.rows() > 0) out.base.row(k) = s.base.row(i);
  }
  return out;
}

// The structurally nonzero columns then the torques, one row per sample (samples x (S + dof)), into
// `all`: one filter pass treats every column alike, and a column that is zero by construction is
// never held.
void columnsAndTorques(const Robot& robot, const JointSignals& s, Eigen::Ref<Eigen::MatrixXd> all) {
  const Eigen::Index structural = robot.structuralColumnCount();
  structuralColumns(robot, s, all.leftCols(structural));
  all.rightCols(robot.dof()) = s.tau_Nm;
}

Eigen::MatrixXd columnsAndTorques(const Robot& robot, const JointSignals& s) {
  Eigen::MatrixXd all(s.size(), robot.structuralColumnCount() + robot.dof());
  columnsAndTorques(robot, s, all);
  return all;
}

// `all` (filtered) at rows first, first + r, ... into out's W and y (m samples), the states' torques
// the processed ones.
void keptRows(const Robot& robot, const Eigen::Ref<const Eigen::MatrixXd>& all, Eigen::Index first, int r, RecordRows& out) {
  const Eigen::Index dof = robot.dof(), m = out.states.size(), structural = robot.structuralColumnCount();
  out.dof = dof;
  out.W = Eigen::MatrixXd::Zero(m * dof, robot.parameters());
  out.y.resize(m * dof);
  out.record_rows = {m * dof};
  for (Eigen::Index k = 0; k < m; ++k) {
    const Eigen::Index i = first + k * r;
    Eigen::Index at = 0;
    for (Eigen::Index j = 0; j < dof; ++j) {
      for (const int c : robot.joint_columns[static_cast<std::size_t>(j)]) out.W(k * dof + j, c) = all(i, at++);
      out.y[k * dof + j] = all(i, structural + j);
      out.states.tau_Nm(k, j) = out.y[k * dof + j];
    }
  }
}

// Rows kept of a record of n samples: first = trim, every r-th up to n - 1 - trim.
Eigen::Index keptCount(Eigen::Index first, Eigen::Index last, int r) { return last < first ? 0 : (last - first) / r + 1; }

}  // namespace

RecordRows recordRows(const Robot& robot, const JointSignals& s) {
  checkJoints(robot, s);
  const Eigen::Index n = s.size(), dof = robot.dof();
  RecordRows out;
  out.dof = dof;
  out.W.resize(n * dof, robot.parameters());
  out.y.resize(n * dof);
  out.record_rows = {n * dof};
  RobotWorkspace work;
  Eigen::VectorXd q(dof), qd(dof), qdd(dof);
  for (Eigen::Index i = 0; i < n; ++i) {
    q = s.q_rad.row(i).transpose();
    qd = s.qd_radps.row(i).transpose();
    qdd = s.qdd_radps2.row(i).transpose();
    robotRowsInto(robot, q, qd, qdd, baseMotionAt(robot, s, i), work, out.W.middleRows(i * dof, dof));
    out.y.segment(i * dof, dof) = s.tau_Nm.row(i).transpose();
  }
  out.states = s;
  return out;
}

RecordRows parallelProcess(const JointSignals& s, const Robot& robot, const SignalOptions& o, double sample_rate_hz) {
  o.validateFor(sample_rate_hz);
  checkJoints(robot, s);
  const double fs = sample_rate_hz;
  const Eigen::Index trim = o.edgeTrimSamples(fs);
  const int r = o.decimationFactor(fs);
  checkRecordLength(s.size(), trim, r);
  Eigen::MatrixXd all = columnsAndTorques(robot, s);
  if (o.filter) filtfiltInPlace(butterworthLowpass(o.filter_order, o.cutoff_hz, fs), all);
  RecordRows out;
  out.states = keptStates(s, trim, keptCount(trim, s.size() - 1 - trim, r), r);
  keptRows(robot, all, trim, r, out);
  return out;
}

RecordRows processRecord(const Dataset& d, const Robot& robot, const SignalOptions& options, const BandRule& rule,
                         std::optional<BandChoice>* chosen) {
  d.requireJoints(robot.jointNames(), "robot '" + robot.chain.name + "'");
  if (chosen) chosen->reset();
  if (options.processing == Processing::kPaper) return recordRows(robot, prepareSignals(d, options));
  const SignalOptions o = resolveSignalOptions(d, robot, options, rule, chosen);
  const double fs = 1.0 / d.sampleInterval_s();
  o.validateFor(fs);
  const Eigen::Index n = d.size();
  // A block holds block_samples rows of up to kBlockColumns columns (regressor and torques side by
  // side): a robot with more gets proportionally fewer samples a block (but at least four margins),
  // so memory stays bounded by the threads times the block, not by the log or the robot's width.
  const Eigen::Index columns = robot.structuralColumnCount() + robot.dof();
  const Eigen::Index margin = parallelBlockMargin(o, fs),
                     block = std::max<Eigen::Index>(o.block_samples * kBlockColumns / std::max(columns, kBlockColumns), 4 * margin);
  if (n <= block + 2 * margin) return parallelProcess(differentiatedStates(d, o), robot, o, fs);
  // A long log, a block at a time with `margin` samples of context on each side: memory stays
  // bounded by the block, and the kept rows are the full-length ones to rounding (the margin).
  const Eigen::Index trim = o.edgeTrimSamples(fs);
  const int r = o.decimationFactor(fs);
  checkRecordLength(n, trim, r);
  struct Block {
    Eigen::Index lo, hi, first, last;  // context [lo, hi); kept rows first, first + r, ... <= last (global)
  };
  std::vector<Block> blocks;
  for (Eigen::Index a = 0; a < n; a += block) {
    const Eigen::Index b = std::min(n, a + block), lo = std::max<Eigen::Index>(0, a - margin), hi = std::min(n, b + margin);
    // Kept global rows: trim + k r within [a, b) and [trim, n - trim).
    const Eigen::Index first_g = std::max(a, trim), last_g = std::min(b, n - trim) - 1;
    if (last_g < first_g) continue;
    const Eigen::Index first_k = first_g + (r - (first_g - trim) % r) % r;
    if (first_k > last_g) continue;
    blocks.push_back({lo, hi, first_k, last_g});
  }
  std::vector<RecordRows> parts(blocks.size());
  const SosFilter lowpass = o.filter ? butterworthLowpass(o.filter_order, o.cutoff_hz, fs) : SosFilter{};
  // Each worker fills and filters its blocks in one buffer of its own, allocated once: a fresh one
  // per block is memory the kernel zeroes again every time.
  std::vector<Eigen::MatrixXd> buffers(static_cast<std::size_t>(core::resolveThreads(o.threads)));
  core::parallelForWorkers(blocks.size(), o.threads, [&](std::size_t k, std::size_t worker) {
    const Block& bk = blocks[k];
    JointSignals s = differentiatedStates(d, o, bk.lo, bk.hi);
    checkJoints(robot, s);
    Eigen::MatrixXd& buffer = buffers[worker];
    if (buffer.rows() < s.size()) buffer.resize(block + 2 * margin, columns);
    auto all = buffer.topRows(s.size());
    columnsAndTorques(robot, s, all);
    parts[k].states = keptStates(s, bk.first - bk.lo, keptCount(bk.first, bk.last, r), r);
    s = JointSignals{};
    if (o.filter) filtfiltInPlace(lowpass, all);
    keptRows(robot, all, bk.first - bk.lo, r, parts[k]);
  });
  // The blocks are the processing's, not the record's: still one record.
  RecordRows out = stackRecords(parts);
  out.record_rows = {out.W.rows()};
  return out;
}

RecordRows stackRecords(const std::vector<RecordRows>& records) {
  if (records.empty()) throw std::invalid_argument("stackRecords: no records");
  if (records.size() == 1) return records.front();
  const RecordRows& first = records.front();
  const bool base = first.states.base.rows() > 0;
  Eigen::Index rows = 0, samples = 0;
  for (const RecordRows& r : records) {
    if (r.dof != first.dof || r.W.cols() != first.W.cols()) {
      throw std::invalid_argument("stackRecords: records of different robots (joints or parameters differ)");
    }
    if ((r.states.base.rows() > 0) != base) {
      throw std::invalid_argument("stackRecords: some records have base-motion columns and others not");
    }
    if (r.states.size() != r.samples()) throw std::invalid_argument("stackRecords: a record's states do not align with its rows");
    rows += r.W.rows();
    samples += r.states.size();
  }
  RecordRows out;
  out.dof = first.dof;
  out.W.resize(rows, first.W.cols());
  out.y.resize(rows);
  JointSignals& st = out.states;
  const Eigen::Index dof = first.dof;
  st.t_s.resize(samples);
  st.q_rad.resize(samples, dof);
  st.qd_radps.resize(samples, dof);
  st.qdd_radps2.resize(samples, dof);
  st.tau_Nm.resize(samples, dof);
  if (base) st.base.resize(samples, 4);
  Eigen::Index at = 0, at_s = 0;
  for (const RecordRows& r : records) {
    out.record_rows.insert(out.record_rows.end(), r.record_rows.begin(), r.record_rows.end());
    out.W.middleRows(at, r.W.rows()) = r.W;
    out.y.segment(at, r.y.size()) = r.y;
    const Eigen::Index m = r.states.size();
    st.t_s.segment(at_s, m) = r.states.t_s;
    st.q_rad.middleRows(at_s, m) = r.states.q_rad;
    st.qd_radps.middleRows(at_s, m) = r.states.qd_radps;
    st.qdd_radps2.middleRows(at_s, m) = r.states.qdd_radps2;
    st.tau_Nm.middleRows(at_s, m) = r.states.tau_Nm;
    if (base) st.base.middleRows(at_s, m) = r.states.base;
    at += r.W.rows();
    at_s += m;
  }
  return out;
}

BandChoice chooseBand(const Dataset& d, const Robot& robot, const SignalOptions& base, const BandRule& rule) {
  d.requireJoints(robot.jointNames(), "robot '" + robot.chain.name + "'");
  const Eigen::Index dof = robot.dof(), first = rule.first_moving_joint;
  if (first >= dof) {
    throw std::invalid_argument("band rule: first_moving_joint " + core::toText(first) + " of a " + core::toText(dof) + "-joint robot");
  }
  // The pilot: least squares of the moving joints' equations at the pilot band (the locked joints'
  // torque is the lock's), its torque predicted from the measured states.
  return chooseBandWith(d, base, rule, [&](const Dataset& record, const SignalOptions& pilot_asked) {
    // The pilot is the full model: the base-motion terms whenever the record has them (they are
    // judged afterwards, in the band chosen).
    SignalOptions pilot = pilot_asked;
    if (pilot.base_terms == BaseTerms::kJudged) pilot.base_terms = BaseTerms::kAuto;
    const RecordRows rows = processRecord(record, robot, pilot);
    LsOptions ls;
    ls.max_condition = std::numeric_limits<double>::max();  // a pilot: its prediction is used, not its parameters
    const Eigen::VectorXd theta = first == 0 ? solveLeastSquares(rows.W, rows.y, ls).x
                                             : solveLeastSquares(rows.W(rows.rowsOfJointsFrom(first), Eigen::all),
                                                                 rows.y(rows.rowsOfJointsFrom(first)), ls).x;
    // One pass over the states (no full-rate rows held): the predicted torque itself.
    const Eigen::MatrixXd predicted = predictTorques(robot, differentiatedStates(record, pilot), theta, pilot.threads);
    PilotTorques t;
    t.predicted_Nm = predicted.rightCols(dof - first);
    t.measured_Nm = record.tau_Nm.rightCols(dof - first);
    return t;
  });
}

namespace {

// The band's and the derivative pre-filter's choices.
SignalOptions resolveBand(const Dataset& d, const Robot& robot, const SignalOptions& o, const BandRule& rule, std::optional<BandChoice>* chosen) {
  if (o.processing != Processing::kParallel || !(o.cutoff_from_data || o.derivative_cutoff_from_data)) return o;
  if (o.cutoff_from_data && o.filter) {
    const BandChoice band = chooseBand(d, robot, o, rule);
    if (chosen) *chosen = band;
    return withBand(o, band);
  }
  SignalOptions r = o;
  r.cutoff_from_data = false;  // unfiltered (--no-filter): no band to choose
  if (o.derivative_cutoff_from_data) {
    r.derivative_cutoff_from_data = false;
    r.derivative_cutoff_hz = derivativeCutoffFor(o.cutoff_hz, 1.0 / d.sampleInterval_s(), rule);
  }
  return r;
}

}  // namespace

SignalOptions resolveSignalOptions(const Dataset& d, const Robot& robot, const SignalOptions& o, const BandRule& rule,
                                   std::optional<BandChoice>* chosen, std::optional<BaseTermsChoice>* base_terms) {
  if (chosen) chosen->reset();
  if (base_terms) base_terms->reset();
  SignalOptions r = resolveBand(d, robot, o, rule, chosen);
  // The terms are judged in the band chosen with them (the full model's). Kept, or nothing to judge:
  // kAuto, so a record processed with these options later (a validation record) uses its IMU
  // columns when it has them, as the default does, and is not judged again.
  if (r.processing == Processing::kParallel && r.base_terms == BaseTerms::kJudged) {
    r.base_terms = BaseTerms::kAuto;
    if (hasBaseColumns(d)) {
      const BaseTermsChoice c = chooseBaseTerms(d, robot, r, rule);
      if (!c.use) r.base_terms = BaseTerms::kOff;
      if (base_terms) *base_terms = c;
    }
  }
  return r;
}

}  // namespace exoid::ident
