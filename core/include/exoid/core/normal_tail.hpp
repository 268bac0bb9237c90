#pragma once
// The standard normal's upper tail, 1 - Phi(z): the level a significance in standard errors means.
#include <cmath>

namespace exoid::core {

inline double normalUpperTail(double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); }

}  // namespace exoid::core
