#include "exoid/experiments/protocol/excitation_report.hpp"

#include "exoid/experiments/report/table.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace exoid::experiments {

namespace {

Excitation excitation(bool full_rank, double condition, const Eigen::VectorXd& collinearity_r2, const std::vector<std::string>& names) {
  Excitation e;
  e.condition = full_rank ? condition : std::numeric_limits<double>::infinity();
  if (!std::isfinite(e.condition)) return e;  // rank deficient: the determination says which columns
  for (Eigen::Index j = 0; j < collinearity_r2.size(); ++j) {
    const double r2 = collinearity_r2[j];
    if (r2 > 0.95) e.collinear.emplace_back(names[static_cast<std::size_t>(j)], r2);
  }
  std::stable_sort(e.collinear.begin(), e.collinear.end(), [](const auto& x, const auto& y) { return x.second > y.second; });
  return e;
}

}  // namespace

Excitation excitationOf(const ident::LsResult& ls, const std::vector<std::string>& names) {
  return excitation(ls.rank == ls.collinearity_r2.size(), ls.condition_number, ls.collinearity_r2, names);
}

Excitation excitationOf(const ident::Estimate& ls, const std::vector<std::string>& names) {
  const bool full_rank = ls.rank && *ls.rank == ls.x.size() && ls.condition_number;
  return excitation(full_rank, ls.condition_number.value_or(0.0), ls.collinearity_r2, names);
}

std::string describe(const Excitation& e, const std::string& of, const std::string& advice) {
  std::string s = "excitation of " + of + ": condition number " + (std::isfinite(e.condition) ? fmt(e.condition, 4) : std::string("inf"));
  if (!e.collinear.empty()) {
    s += "; nearly collinear (R^2 on the other columns > 0.95, model errors amplified):";
    for (const auto& [name, r2] : e.collinear) s += " " + name + " R^2 " + fixed(r2, 4) + " (x" + fmt(1.0 / std::sqrt(1.0 - r2), 3) + ")";
  }
  if (e.condition > 100.0 || !e.collinear.empty()) s += ". " + advice;
  return s;
}

}  // namespace exoid::experiments
