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
  /// Same half-width w in every dimension around centre c: [c - w, c + w].
  static Box around(const Eigen::Ref<const Eigen::VectorXd>& centre, double half_width);
  static Box uniform(Eigen::Index dim, double lower, double upper);
};

}  // namespace exoid::ident
