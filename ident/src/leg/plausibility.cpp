#include "exoid/ident/leg/plausibility.hpp"

#include <algorithm>
#include <cstdio>

namespace exoid::ident {
namespace {

std::string describe(const char* what, double value, const char* unit, const char* must) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s = %.6g %s must be %s", what, value, unit, must);
  return buf;
}

}  // namespace

std::vector<std::string> implausibilities(const ParamVector& x, const std::vector<int>& not_estimated) {
  const auto estimated = [&](int i) {
    return std::find(not_estimated.begin(), not_estimated.end(), i) == not_estimated.end();
  };
  std::vector<std::string> out;
  if (estimated(kJs) && !(x[kJs] > 0.0)) out.push_back(describe("Js", x[kJs], "kg m^2", "> 0"));
  if (estimated(kJt) && estimated(kJs) && !(x[kJt] > x[kJs])) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "Jt = %.6g kg m^2 must be > Js = %.6g kg m^2 (the thigh adds inertia)", x[kJt], x[kJs]);
    out.emplace_back(buf);
  }
  for (const int i : {kFc1, kFv1, kFc2, kFv2}) {
    if (estimated(i) && !(x[i] >= 0.0)) {
      out.push_back(describe(paramInfo()[static_cast<std::size_t>(i)].name, x[i], paramInfo()[static_cast<std::size_t>(i)].unit,
                             ">= 0 (friction dissipates)"));
    }
  }
  return out;
}

}  // namespace exoid::ident
