#include "exoid/ident/model/chain_estimate.hpp"

#include "exoid/core/format.hpp"

#include <Eigen/Cholesky>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace exoid::ident {

ChainEstimate estimateChain(const ChainModel& model, const BaseParameters& base, const ChainRecord& record,
                            const Eigen::VectorXd& phi_start, const ChainEstimateOptions& options) {
  const Eigen::Index p = model.standardParameterCount();
  if (record.W.cols() != p || record.W.rows() != record.y.size() || phi_start.size() != p) {
    throw std::invalid_argument("chain estimate: expected " + core::toText(p) + " regressor columns and a start of " + core::toText(p) +
                                " standard parameters for model '" + model.name + "'");
  }
  ChainEstimate out;
  out.names = base.names;
  out.rows = record.W.rows();
  const Eigen::MatrixXd Wb = base.baseRegressor(record.W);
  out.ls = solveLeastSquares(Wb, record.y, options.ls);
  out.beta = out.ls.x;
  out.std_error = Eigen::VectorXd::Constant(base.rank, std::numeric_limits<double>::quiet_NaN());
  const bool full_rank = out.ls.rank == base.rank;
  if (full_rank && out.rows > base.rank) {
    const Eigen::MatrixXd A = Wb.transpose() * Wb;
    const double rss = (record.y - Wb * out.beta).squaredNorm();
    const double sigma2 = rss / static_cast<double>(out.rows - base.rank);
    out.std_error = (sigma2 * A.ldlt().solve(Eigen::MatrixXd::Identity(base.rank, base.rank)).diagonal()).cwiseMax(0.0).cwiseSqrt();
    if (options.consistent) {
      out.consistent = consistentFitNormal(model, base, A, Wb.transpose() * record.y, record.y.squaredNorm(), phi_start, options.consistent_fit);
    }
  }
  return out;
}

}  // namespace exoid::ident
