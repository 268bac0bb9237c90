#pragma once
// One entry point per identification method over a linear problem y = H x, with one result
// shape, so callers (CLI, segmental strategy, sweeps) treat methods alike.
#include "exoid/ident/estimators/lad.hpp"
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/estimators/rls_pso.hpp"

#include <optional>
#include <string>
#include <vector>

namespace exoid::ident {

enum class Method {
  kLs,      ///< least squares by column-pivoted QR (paper Eq. 5)
  kRls,     ///< final RLS estimate (paper Eq. 6)
  kPso,     ///< PSO over a wide box (the paper's "PSO" baseline)
  kRlsPso,  ///< RLS box + PSO (the paper's method)
  kLad,     ///< exact minimum of the L1 cost (reference the paper lacks)
  /// Instrumental variables from closed-loop simulations of the model (idim_iv.hpp). Not a
  /// method over y = H x alone: estimate() rejects it; it needs records and their controller.
  kIdimIv,
  /// Instrumental variables from the motion's band (band_iv.hpp): needs no controller model, but
  /// the records themselves, not y = H x alone: estimate() rejects it.
  kIvBand,
};
const char* toString(Method m);  ///< "ls", "rls", "pso", "rls-pso", "lad", "idim-iv", "iv-band"
/// Parses a method name (allMethods(), "idim-iv" or "iv-band"); throws std::invalid_argument listing them.
Method parseMethod(const std::string& name);
/// The methods over a linear problem y = H x (estimate() runs them): all but kIdimIv and kIvBand.
const std::vector<Method>& allMethods();

struct MethodOptions {
  LsOptions ls;
  RlsPsoOptions rls_pso;  ///< RLS, range and PSO settings (PSO settings shared with kPso)
  LadOptions lad;
  /// The PSO baseline's box: [-wide_box_half_width, +wide_box_half_width] in every parameter,
  /// standing in for the paper's "infinite domain". Range > 0. Default 50 (about 10x the
  /// largest parameter of an APAL-sized leg, in SI units).
  double wide_box_half_width = 50.0;
  /// Also solve the exact L1 minimum, unconstrained and over the search box, and report each PSO
  /// and RLS-PSO run's optimality gaps against them.
  bool report_optimality_gap = true;
  void validate() const;
};

/// The PSO baseline's box sized from the data, every leg's default: 10 x the largest |LS
/// estimate| (a fixed +-50 is absurd for a 0.3 kg arm and tiny for a heavy leg), at least 1e-5.
/// Throws std::invalid_argument when the estimate is empty or not finite.
double psoHalfWidthFromLs(const Eigen::VectorXd& ls_estimate);

struct Estimate {
  Method method = Method::kLs;
  Eigen::VectorXd x;
  Summary summary;
  double l1_cost = 0.0;                   ///< sum |y - H x| of the estimate (the paper's cost)
  std::optional<Eigen::Index> rank;       ///< LS: numerical rank
  /// Of the column-scaled regressor (every method; IDIM-IV: of Z^T H, the matrix it solves)
  std::optional<double> condition_number;
  std::vector<Eigen::Index> unidentifiable;  ///< LS: columns beyond the rank
  Eigen::VectorXd collinearity_r2;          ///< LS: each column's R^2 on the others (LsResult's)
  std::optional<Box> box;                  ///< PSO / RLS-PSO search box; RLS fluctuation range
  std::vector<double> cost_history;        ///< PSO: best cost per iteration
  std::optional<double> optimum_l1_cost;   ///< exact L1 minimum (when report_optimality_gap)
  /// (l1_cost - optimum) / optimum: how far the estimate is from the best the cost allows.
  std::optional<double> optimality_gap_rel;
  /// PSO, RLS-PSO: exact L1 minimum over the same box (certified, solveBoxedLeastAbsoluteDeviations)
  /// and the gap against it: what the search itself failed to find inside its box.
  std::optional<double> optimum_box_l1_cost;
  std::optional<double> optimality_gap_box_rel;
};

/// Runs one method on y = H x. Precondition failures throw std::invalid_argument; numerical
/// trouble is reported in summary.status.
Estimate estimate(Method method, const Eigen::MatrixXd& H, const Eigen::VectorXd& y,
                  const MethodOptions& options);

}  // namespace exoid::ident
