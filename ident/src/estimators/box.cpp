#include "exoid/ident/estimators/box.hpp"

#include "exoid/core/format.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace exoid::ident {

bool Box::contains(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  return x.size() == dim() && (x.array() >= lower.array()).all() && (x.array() <= upper.array()).all();
}

void Box::validate() const {
  if (lower.size() != upper.size() || lower.size() == 0) {
    throw std::invalid_argument("box: lower and upper must have the same non-zero size, got " +
                                core::toText(lower.size()) + " and " + core::toText(upper.size()));
  }
  for (Eigen::Index i = 0; i < lower.size(); ++i) {
    if (!std::isfinite(lower[i]) || !std::isfinite(upper[i]) || !(lower[i] < upper[i])) {
      throw std::invalid_argument("box: dimension " + core::toText(i) +
                                  " needs finite lower < upper, got [" + core::toText(lower[i]) +
                                  ", " + core::toText(upper[i]) + "]");
    }
  }
}

Box Box::uniform(Eigen::Index dim, double lo, double hi) {
  return Box{Eigen::VectorXd::Constant(dim, lo), Eigen::VectorXd::Constant(dim, hi)};
}

}  // namespace exoid::ident
