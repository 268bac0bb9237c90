#include "exoid/ident/design/identifiability_advice.hpp"

#include "exoid/core/format.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace exoid::ident {

namespace {

// What motion informs a parameter, by its kind.
std::string needs(ParameterKind kind) {
  switch (kind) {
    case ParameterKind::kMass:
    case ParameterKind::kFirstMoment:
      return "the link angles to sweep a wide range (gravity's sine and cosine terms must both vary)";
    case ParameterKind::kInertia:
      return "large joint accelerations, at more than one frequency";
    case ParameterKind::kCoulomb:
      return "the joint to reverse direction often, at speed";
    case ParameterKind::kViscous:
      return "a wide range of joint speeds";
    case ParameterKind::kArmature:
      return "the joint accelerating differently from the joints above it (its column differs from its link's inertia only then)";
  }
  return "more varied motion";
}

std::string percent(double v) { return core::formatNumber(100.0 * v, 3) + " %"; }

}  // namespace

std::vector<std::string> identifiabilityAdvice(const Eigen::MatrixXd& H, const IdentifiabilityReport& r, const Robot& robot,
                                               const std::vector<int>& params, const AdviceOptions& o) {
  const Eigen::Index p = H.cols();
  if (static_cast<Eigen::Index>(params.size()) != p || r.crb_rel_std.size() != p || r.collinearity_r2.size() != p) {
    throw std::invalid_argument("identifiability advice: the report, the regressor and the parameter list disagree in size");
  }
  for (int i : params) {
    if (i < 0 || i >= robot.parameters()) throw std::invalid_argument("identifiability advice: parameter " + core::toText(i) + " is not the robot's");
  }
  // The column each one is most nearly parallel to: largest |cos| between unit columns.
  Eigen::MatrixXd U = H;
  for (Eigen::Index j = 0; j < p; ++j) {
    const double n = U.col(j).norm();
    if (n > 0) U.col(j) /= n;
  }
  const Eigen::MatrixXd G = U.transpose() * U;
  const auto partner = [&](Eigen::Index j) {
    Eigen::Index best = j == 0 ? 1 : 0;
    for (Eigen::Index k = 0; k < p; ++k) {
      if (k != j && std::abs(G(j, k)) > std::abs(G(j, best))) best = k;
    }
    return best;
  };
  const std::vector<ParameterKind> kinds = parameterKinds(robot);
  const auto name = [&](Eigen::Index j) { return robot.names()[static_cast<std::size_t>(params[static_cast<std::size_t>(j)])]; };

  std::vector<std::string> out;
  std::vector<bool> unidentifiable(static_cast<std::size_t>(p), false);
  for (Eigen::Index j : r.unidentifiable) unidentifiable[static_cast<std::size_t>(j)] = true;
  for (Eigen::Index j = 0; j < p; ++j) {
    const ParameterKind kind = kinds[static_cast<std::size_t>(params[static_cast<std::size_t>(j)])];
    if (p < 2) break;
    const Eigen::Index q = partner(j);
    if (unidentifiable[static_cast<std::size_t>(j)]) {
      out.push_back(name(j) + " cannot be identified from this record: its column is a combination of the others (most "
                    "nearly " + name(q) + "'s, |cos| = " + core::formatFixed(std::abs(G(j, q)), 6) + "). It needs " + needs(kind) + ".");
    } else if (std::isnan(r.crb_rel_std[j])) {  // no reference to be relative to: collinearity alone
      if (r.collinearity_r2[j] > o.poor_collinearity) {
        out.push_back(name(j) + " is poorly determined: " + core::formatNumber(100.0 * r.collinearity_r2[j], 4) +
                      " % of its column is explained by the others (most by " + name(q) + ", |cos| = " +
                      core::formatFixed(std::abs(G(j, q)), 4) + "), so its std is " +
                      core::formatNumber(1.0 / std::sqrt(1.0 - r.collinearity_r2[j]), 3) +
                      "x an unconfounded column's. It needs " + needs(kind) + ".");
      }
    } else if (!(r.crb_rel_std[j] <= o.poor_relative_std)) {
      out.push_back(name(j) + " is poorly determined: relative std " + percent(r.crb_rel_std[j]) + " at this noise; " +
                    core::formatNumber(100.0 * r.collinearity_r2[j], 4) + " % of its column is explained by the others (most by " +
                    name(q) + ", |cos| = " + core::formatFixed(std::abs(G(j, q)), 4) + "). It needs " + needs(kind) + ".");
    }
  }
  if (!std::isfinite(r.condition_number) || r.condition_number > o.poor_condition) {
    Eigen::Index a = 0, b = 1;
    for (Eigen::Index j = 0; j < p; ++j) {
      for (Eigen::Index k = j + 1; k < p; ++k) {
        if (std::abs(G(j, k)) > std::abs(G(a, b))) {
          a = j;
          b = k;
        }
      }
    }
    out.push_back("The excitation is poor: condition number " +
                  (std::isfinite(r.condition_number) ? core::formatNumber(r.condition_number, 4) : std::string("inf")) +
                  " (columns scaled; above " + core::formatNumber(o.poor_condition, 4) + " small model errors move the estimate a lot). "
                  "The most nearly parallel columns are " + name(a) + " and " + name(b) + " (|cos| = " +
                  core::formatFixed(std::abs(G(a, b)), 6) + "). A designed trajectory separates them: `exoid excite`.");
  }
  if (out.empty()) {
    const bool relative = p > 0 && !std::isnan(r.crb_rel_std[0]);
    out.push_back("Well excited: condition number " + core::formatNumber(r.condition_number, 4) + ", every parameter " +
                  (relative ? "within " + percent(o.poor_relative_std) + " relative std at this noise."
                            : "with at most " + percent(o.poor_collinearity) + " of its column explained by the others."));
  }
  return out;
}

}  // namespace exoid::ident
