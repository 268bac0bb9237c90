#include "exoid/core/format.hpp"

#include <cstdio>

namespace exoid::core {

std::string formatNumber(double v, int significant) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", significant, v);
  return buf;
}

std::string formatFixed(double v, int decimals) {
  char buf[400];  // %f of 1e308 has 309 digits before the point
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

}  // namespace exoid::core
