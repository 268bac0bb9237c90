#pragma once
// An axis-aligned search box (PSO's domain, RLS's fluctuation range).
#include <Eigen/Core>

namespace exoid::ident {

struct Box {
  Eigen::VectorXd lower;
  Eigen::VectorXd upper;
  Eigen::Index dim() const { return lower.size(); }
  bool contains(const Eigen::Ref<const Eigen::VectorXd>& x) const;
  /// Throws std::invalid_argument unless sizes agree, values are finite and lower < upper.
  void validate() const;
  static Box uniform(Eigen::Index dim, double lower, double upper);
};

}  // namespace exoid::ident
