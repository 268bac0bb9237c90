#include "exoid/ident/estimators/idim_iv.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/estimators/stopwatch.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace exoid::ident {

void IvOptions::validate() const {
  ls.validate();
  if (!(step_tolerance > 0 && step_tolerance < 1)) {
    throw std::invalid_argument("'step_tolerance' must be in (0, 1), got " + core::toText(step_tolerance));
  }
  if (max_iterations < 1) throw std::invalid_argument("'max_iterations' must be >= 1, got " + core::toText(max_iterations));
}

namespace {

void checkShapes(const Eigen::MatrixXd& H, const Eigen::VectorXd& y, const Eigen::MatrixXd& Z) {
  if (H.rows() != y.size() || Z.rows() != H.rows() || Z.cols() != H.cols()) {
    std::ostringstream ss;
    ss << "instrumental variables: H is " << H.rows() << " x " << H.cols() << ", y has " << y.size()
       << " rows, Z is " << Z.rows() << " x " << Z.cols() << " (Z must match H)";
    throw std::invalid_argument(ss.str());
  }
  if (H.rows() < H.cols()) throw std::invalid_argument("instrumental variables: fewer rows than parameters");
  if (!H.allFinite() || !y.allFinite() || !Z.allFinite()) {
    throw std::invalid_argument("instrumental variables: NaN or Inf in H, y or Z");
  }
}

// Standard error of each parameter of x = A^{-1} Z^T y, A = Z^T H: sigma^2 A^{-1} Z^T Z A^{-T}.
Eigen::VectorXd ivStandardErrors(const Eigen::MatrixXd& H, const Eigen::VectorXd& y, const Eigen::MatrixXd& Z,
                                 const Eigen::VectorXd& x) {
  const Eigen::Index n = H.rows(), p = H.cols();
  const double sigma2 = (y - H * x).squaredNorm() / static_cast<double>(std::max<Eigen::Index>(1, n - p));
  const Eigen::MatrixXd a = Z.transpose() * H;
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  const Eigen::MatrixXd ainv_zt = qr.solve(Z.transpose());
  return (sigma2 * (ainv_zt * ainv_zt.transpose()).diagonal()).cwiseMax(0.0).cwiseSqrt();
}

}  // namespace

Estimate instrumentalVariables(const Eigen::MatrixXd& H, const Eigen::VectorXd& y, const Eigen::MatrixXd& Z,
                               const LsOptions& options) {
  options.validate();
  checkShapes(H, y, Z);
  const Stopwatch watch;
  Estimate e;
  e.method = Method::kIdimIv;
  // Scale columns by H's norms so the pivoting and the rank threshold see comparable columns.
  const Eigen::VectorXd s = columnScales(H);
  const Eigen::MatrixXd a = (Z * s.asDiagonal()).transpose() * (H * s.asDiagonal());
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  qr.setThreshold(options.rank_tolerance);
  e.rank = qr.rank();
  const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(a).singularValues();
  e.condition_number = sv[sv.size() - 1] > 0 ? sv[0] / sv[sv.size() - 1] : INFINITY;
  e.x = s.asDiagonal() * qr.solve((Z * s.asDiagonal()).transpose() * y);
  e.summary.iterations = 1;
  if (qr.rank() < H.cols()) {
    for (Eigen::Index k = qr.rank(); k < H.cols(); ++k) e.unidentifiable.push_back(qr.colsPermutation().indices()[k]);
    e.summary.status = Status::kRankDeficient;
    e.summary.message = "Z^T H is singular: the instruments do not separate " + core::toText(H.cols() - qr.rank()) + " column(s)";
  } else {
    e.summary.status = Status::kConverged;
    e.summary.message = "instrumental-variable solve";
  }
  e.l1_cost = (y - H * e.x).cwiseAbs().sum();
  e.summary.final_cost = e.l1_cost;
  e.summary.wall_time_s = watch.seconds();
  return e;
}

Estimate iterateInstrumentalVariables(const Eigen::MatrixXd& H, const Eigen::VectorXd& y, const InstrumentFn& instruments,
                                      const IvOptions& options) {
  options.validate();
  const Stopwatch watch;
  const LsResult ls = solveLeastSquares(H, y, options.ls);
  Estimate e;
  e.method = Method::kIdimIv;
  e.x = ls.x;
  e.rank = ls.rank;
  e.condition_number = ls.condition_number;
  e.unidentifiable = ls.unidentifiable;
  e.summary.initial_cost = (y - H * ls.x).cwiseAbs().sum();
  auto finish = [&](Status status, const std::string& message) {
    e.summary.status = status;
    e.summary.message = message;
    e.l1_cost = (y - H * e.x).cwiseAbs().sum();
    e.summary.final_cost = e.l1_cost;
    e.summary.wall_time_s = watch.seconds();
    return e;
  };
  if (!usable(ls.summary.status)) return finish(ls.summary.status, "starting LS: " + ls.summary.message);
  for (int k = 1; k <= options.max_iterations; ++k) {
    const Instruments z = instruments(e.x);
    if (!z.ok) return finish(Status::kFailed, "iteration " + core::toText(k) + ": " + z.message);
    checkShapes(H, y, z.Z);
    const Estimate iv = instrumentalVariables(H, y, z.Z, options.ls);
    e.summary.iterations = k;
    if (!usable(iv.summary.status)) {
      e.unidentifiable = iv.unidentifiable;
      return finish(iv.summary.status, "iteration " + core::toText(k) + ": " + iv.summary.message);
    }
    if (z.fixed) {
      e.x = iv.x;
      e.condition_number = iv.condition_number;
      return finish(Status::kConverged, "IDIM-IV: " + z.message + "; one solve with them after " + core::toText(k - 1) +
                                            " iteration(s)");
    }
    const Eigen::VectorXd se = ivStandardErrors(H, y, z.Z, iv.x);
    // Each step in units of the parameter's standard error; the floor keeps noise-free data
    // (se = 0) from demanding steps below roundoff times the conditioning of Z^T H (~1e-10).
    const Eigen::VectorXd floor = Eigen::VectorXd::Constant(se.size(), 1e-8 * iv.x.cwiseAbs().maxCoeff());
    const double step = ((iv.x - e.x).cwiseAbs().array() / (se + floor).array()).maxCoeff();
    e.x = iv.x;
    e.condition_number = iv.condition_number;
    e.cost_history.push_back(step);
    if (step <= options.step_tolerance) {
      return finish(Status::kConverged, "IDIM-IV: steps below " + core::toText(options.step_tolerance) +
                                            " standard errors after " + core::toText(k) + " iteration(s)");
    }
  }
  return finish(Status::kMaxIterations, "IDIM-IV: the step was still " + core::toText(e.cost_history.back()) +
                                            " standard errors after " + core::toText(options.max_iterations) + " iterations");
}

Instruments instrumentRows(const Robot& robot, const Eigen::VectorXd& theta, const ClosedLoopRecord& r, RecordRows& out) {
  Instruments z;
  // The rate exactly as processRecord computes it from the record's timestamps.
  const double fs = 1.0 / ((r.reference.t_s[r.reference.size() - 1] - r.reference.t_s[0]) / static_cast<double>(r.reference.size() - 1));
  const ClosedLoopRun run = simulateClosedLoop(robot, theta, r.controller, r.reference);
  if (run.ok) {
    out = parallelProcess(run.states, robot, r.signals, fs);
  } else {
    JointSignals ref;
    ref.t_s = r.reference.t_s;
    ref.q_rad = r.reference.q_rad;
    ref.qd_radps = r.reference.qd_radps;
    ref.qdd_radps2 = r.reference.qdd_radps2;
    ref.tau_Nm = Eigen::MatrixXd::Zero(ref.size(), robot.dof());
    out = parallelProcess(ref, robot, r.signals, fs);
    z.fixed = true;
    z.message = "instruments from the reference (the model of this iteration cannot be simulated: " + run.message + ")";
  }
  if (out.W.rows() != r.measured.W.rows()) {
    throw std::invalid_argument("IDIM-IV: the reference has " + core::toText(r.reference.size()) +
                                " samples but the measured record's rows do not come from as many (process it with the same options)");
  }
  z.ok = true;
  return z;
}

namespace {
void requireParallel(const ClosedLoopRecord& r) {
  if (r.signals.processing != Processing::kParallel || r.signals.cutoff_from_data || r.signals.derivative_cutoff_from_data) {
    throw std::invalid_argument("IDIM-IV needs each record's parallel processing (processing = parallel) with its band fixed: its "
                                "instruments are processed like the measured rows, which the paper's processing cannot do");
  }
}
}  // namespace

Estimate identifyIdimIv(const Robot& robot, const std::vector<ClosedLoopRecord>& records, const IvOptions& options) {
  if (records.empty()) throw std::invalid_argument("IDIM-IV: no records");
  std::vector<RecordRows> measured;
  for (const ClosedLoopRecord& r : records) {
    requireParallel(r);
    measured.push_back(r.measured);
  }
  const RecordRows stacked = stackRecords(measured);
  return iterateInstrumentalVariables(stacked.W, stacked.y, [&](const Eigen::VectorXd& theta) {
    Instruments all;
    all.ok = true;
    all.Z.resize(stacked.W.rows(), stacked.W.cols());
    Eigen::Index row = 0;
    for (const ClosedLoopRecord& r : records) {
      RecordRows instr;
      const Instruments z = instrumentRows(robot, theta, r, instr);
      all.Z.middleRows(row, instr.W.rows()) = instr.W;
      row += instr.W.rows();
      all.fixed = all.fixed || z.fixed;
      if (!z.message.empty()) all.message += (all.message.empty() ? "" : "; ") + z.message;
    }
    return all;
  }, options);
}

SegmentalResult identifySegmentalIdimIv(const Robot& robot, const std::vector<ClosedLoopStage>& stages, const IvOptions& options,
                                        const BaseParameterOptions& structure) {
  std::vector<Eigen::Index> first;
  for (const ClosedLoopStage& st : stages) {
    requireParallel(st.record);
    first.push_back(st.first_joint);
  }
  const SegmentalPlan plan(robot, first, structure);
  SegmentalResult out;
  std::vector<Eigen::VectorXd> found;
  for (int s = 0; s < plan.stages(); ++s) {
    const ClosedLoopRecord& record = stages[static_cast<std::size_t>(s)].record;
    StageResult res;
    res.problem = plan.problem(s, record.measured, found);
    const StageProblem& p = res.problem;
    res.estimate = iterateInstrumentalVariables(p.H, p.y, [&](const Eigen::VectorXd& x) {
      RecordRows instr;
      Instruments z = instrumentRows(robot, p.theta(x), record, instr);
      if (z.ok) {
        z.Z = p.parameters.empty() ? Eigen::MatrixXd(instr.W(p.rows, Eigen::all) * p.directions) : Eigen::MatrixXd(instr.W(p.rows, p.parameters));
      }
      return z;
    }, options);
    res.problem.H.resize(0, 0);
    res.problem.y.resize(0);
    found.push_back(res.estimate.x);
    out.stages.push_back(std::move(res));
  }
  out.theta = plan.assemble(found);
  return out;
}

}  // namespace exoid::ident
