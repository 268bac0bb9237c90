#include "exoid/ident/estimators/segmental_errors.hpp"

#include <Eigen/QR>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace exoid::ident {
namespace {

// One stage's own covariances (its records alone) of its values.
struct StageCovariances {
  Eigen::MatrixXd newey_west, block_jackknife;
  std::optional<Eigen::MatrixXd> record_jackknife;
};

StageCovariances stageCovariances(const StageProblem& p, const RecordRows& record, const Eigen::VectorXd& x) {
  const Eigen::Index samples = record.samples();
  const int rows_per_step = samples > 0 ? static_cast<int>(static_cast<Eigen::Index>(p.rows.size()) / samples) : 1;
  // Rows of the stage's problem per record: each record's samples times the equations fitted.
  std::vector<Eigen::Index> record_rows;
  for (Eigen::Index r : record.record_rows) record_rows.push_back(r / record.dof * rows_per_step);
  const Eigen::Index n = p.H.rows();
  StageCovariances c;
  c.newey_west = residualCovariance(p.H, p.y - p.H * x, interleavedChannels(n, 1), -1, rows_per_step);
  c.block_jackknife = blockJackknifeCovariance(p.H, p.y, recordBlocks(record_rows, n, rows_per_step));
  const std::vector<RowBlock> records = wholeRecords(record_rows, n);
  if (records.size() >= 3) c.record_jackknife = blockJackknifeCovariance(p.H, p.y, records);
  return c;
}

}  // namespace

ReportedErrors segmentalReportedErrors(const Robot& robot, const std::vector<SegmentalStage>& stages, const SegmentalResult& ls,
                                       const BaseParameterOptions& structure) {
  std::vector<Eigen::Index> first;
  for (const SegmentalStage& st : stages) first.push_back(st.first_joint);
  const SegmentalPlan plan(robot, first, structure);
  if (ls.stages.size() != stages.size()) throw std::invalid_argument("segmental errors: the result has another number of stages");
  std::vector<Eigen::VectorXd> found;
  std::vector<Eigen::Index> offset;  // each stage's first value in the values of all stages
  Eigen::Index total = 0;
  for (const StageResult& s : ls.stages) {
    found.push_back(s.estimate.x);
    offset.push_back(total);
    total += s.estimate.x.size();
  }
  // A: each stage's values per unit of an earlier stage's (strictly block lower triangular);
  // D_*: the stages' own covariances, block diagonal.
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(total, total);
  Eigen::MatrixXd nw = Eigen::MatrixXd::Zero(total, total), block = nw, rec = nw;
  bool any_records = false;
  for (int s = 0; s < plan.stages(); ++s) {
    const std::size_t k = static_cast<std::size_t>(s);
    const RecordRows& record = stages[k].record;
    const std::vector<Eigen::VectorXd> before(found.begin(), found.begin() + s);
    const StageProblem p = plan.problem(s, record, before);
    const Eigen::Index m = found[k].size(), at = offset[k];
    const StageCovariances c = stageCovariances(p, record, found[k]);
    nw.block(at, at, m, m) = c.newey_west;
    block.block(at, at, m, m) = c.block_jackknife;
    rec.block(at, at, m, m) = c.record_jackknife ? *c.record_jackknife : c.block_jackknife;
    any_records = any_records || c.record_jackknife.has_value();
    if (s == 0) continue;
    // The torque side is linear in the earlier values: a unit step of each shows its column.
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(p.H);
    std::vector<Eigen::VectorXd> stepped = before;
    for (int e = 0; e < s; ++e) {
      for (Eigen::Index i = 0; i < found[static_cast<std::size_t>(e)].size(); ++i) {
        stepped[static_cast<std::size_t>(e)][i] += 1.0;
        const Eigen::VectorXd dy = plan.problem(s, record, stepped).y - p.y;
        stepped[static_cast<std::size_t>(e)][i] -= 1.0;
        A.block(at, offset[static_cast<std::size_t>(e)] + i, m, 1) = qr.solve(dy);
      }
    }
  }
  // The values of all stages as own errors carried down: (I - A)^-1; then into the robot's
  // parameters (assemble is linear in the values).
  const Eigen::MatrixXd carry = (Eigen::MatrixXd::Identity(total, total) - A).inverse();
  Eigen::MatrixXd T(robot.parameters(), total);
  std::vector<Eigen::VectorXd> unit;
  for (const Eigen::VectorXd& f : found) unit.push_back(Eigen::VectorXd::Zero(f.size()));
  for (std::size_t s = 0; s < found.size(); ++s) {
    for (Eigen::Index i = 0; i < found[s].size(); ++i) {
      unit[s][i] = 1.0;
      T.col(offset[s] + i) = plan.assemble(unit);
      unit[s][i] = 0.0;
    }
  }
  const Eigen::MatrixXd M = T * carry;
  // A stage whose jackknife is infinite (a fit without some block is singular) makes every
  // parameter its values reach infinite, not NaN (inf x 0 in the product).
  const auto carried = [&](const Eigen::MatrixXd& own) {
    const Eigen::MatrixXd finite = own.unaryExpr([](double v) { return std::isfinite(v) ? v : 0.0; });
    Eigen::MatrixXd out = M * finite * M.transpose();
    for (Eigen::Index j = 0; j < total; ++j) {
      if (own.col(j).allFinite()) continue;
      for (Eigen::Index i = 0; i < M.rows(); ++i) {
        if (M(i, j) != 0.0) out(i, i) = std::numeric_limits<double>::infinity();
      }
    }
    return out;
  };
  return combineReportedErrors(carried(nw), carried(block), any_records ? std::optional<Eigen::MatrixXd>(carried(rec)) : std::nullopt);
}

}  // namespace exoid::ident
