#pragma once
// RLS-PSO (paper Fig. 4): RLS's fluctuation range defines the box, PSO searches inside it.
// A composition of runRls, fluctuationRange and minimizePso; nothing is re-implemented here.
#include "exoid/ident/estimators/linear_cost.hpp"
#include "exoid/ident/estimators/pso.hpp"
#include "exoid/ident/estimators/rls.hpp"

namespace exoid::ident {

struct RlsPsoOptions {
  RlsOptions rls;
  FluctuationOptions range;
  PsoOptions pso;
  CostNorm cost = CostNorm::kL1;
};

struct RlsPsoResult {
  RlsResult rls;
  Box box;
  PsoResult pso;
};

RlsPsoResult identifyRlsPso(const Eigen::MatrixXd& H, const Eigen::VectorXd& y,
                            const RlsPsoOptions& options = {});

/// PSO on the linear cost over a given box (the paper's "PSO" baseline uses a wide box).
PsoResult identifyPso(const Eigen::MatrixXd& H, const Eigen::VectorXd& y, const Box& box,
                      const PsoOptions& options, CostNorm cost = CostNorm::kL1);

}  // namespace exoid::ident
