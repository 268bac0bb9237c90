#include "exoid/ident/model/base_estimate.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/estimators/standard_errors.hpp"

#include <Eigen/Cholesky>

#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace exoid::ident {

ChainEstimate estimateChain(const Robot& robot, const RecordRows& record, const Eigen::VectorXd& phi_start,
                            const ChainEstimateOptions& options) {
  const ChainModel& model = robot.chain;
  const BaseParameters& base = robot.basis;
  const Eigen::Index p = model.standardParameterCount();
  if (record.W.cols() != robot.parameters() || record.W.rows() != record.y.size() || phi_start.size() != p) {
    throw std::invalid_argument("chain estimate: expected " + core::toText(robot.parameters()) + " regressor columns and a start of " +
                                core::toText(p) + " standard parameters for model '" + model.name + "'");
  }
  ChainEstimate out;
  out.names = base.names;
  out.rows = record.W.rows();
  const Eigen::MatrixXd& Wb = record.W;
  out.ls = solveLeastSquares(Wb, record.y, options.ls);
  out.beta = out.ls.x;
  out.std_error = Eigen::VectorXd::Constant(base.rank, std::numeric_limits<double>::quiet_NaN());
  const bool full_rank = out.ls.rank == base.rank;
  if (full_rank && out.rows > base.rank) {
    out.normal = Wb.transpose() * Wb;
    const Eigen::MatrixXd& A = out.normal;
    // Each record one channel of Newey-West's, and one block of the record jackknife.
    const std::vector<RowBlock> records = wholeRecords(record.record_rows, out.rows);
    std::vector<Channel> channels;
    for (const RowBlock& r : records) {
      Channel c(static_cast<std::size_t>(r.rows));
      std::iota(c.begin(), c.end(), r.first);
      channels.push_back(std::move(c));
    }
    const int dof = static_cast<int>(std::max<Eigen::Index>(record.dof, 1));
    out.errors = reportedErrors(Wb, record.y, out.beta, channels, dof, recordBlocks(record.record_rows, out.rows, dof), records);
    out.covariance = out.errors.covariance;
    out.std_error = out.errors.reported;
    if (options.consistent) {
      out.consistent = consistentFitNormal(model, base, A, Wb.transpose() * record.y, record.y.squaredNorm(), phi_start, options.consistent_fit);
    }
  }
  return out;
}

}  // namespace exoid::ident
