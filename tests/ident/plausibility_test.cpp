// Physical plausibility: the conditions the parameter definitions imply, against physical legs
// (always plausible) and against estimates that break one condition each.
#include "exoid/ident/leg/plausibility.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <random>

namespace exoid::ident {
namespace {

TEST(Plausibility, EveryPhysicalLegIsPlausible) {
  // Random legs with positive masses and inertias and non-negative friction: toParamVector gives
  // an X that must pass every condition (they are consequences of the definitions).
  std::mt19937_64 gen(4);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 1000; ++k) {
    LegPhysical leg;
    leg.thigh = {0.5 + 20 * u(gen), 0.2 + 0.5 * u(gen), -0.2 + 0.6 * u(gen), -0.3 + 0.6 * u(gen), 1e-4 + 0.5 * u(gen)};
    leg.shank = {0.2 + 8 * u(gen), 0.0, -0.2 + 0.6 * u(gen), -0.3 + 0.6 * u(gen), 1e-4 + 0.3 * u(gen)};
    leg.fc_hip_Nm = 3 * u(gen);
    leg.fv_hip_Nms = 2 * u(gen);
    leg.fc_knee_Nm = u(gen);
    leg.fv_knee_Nms = u(gen);
    EXPECT_TRUE(implausibilities(toParamVector(leg)).empty());
  }
}

TEST(Plausibility, EachViolationIsNamed) {
  const ParamVector ok = toParamVector(defaultLeg());
  struct Case {
    int index;
    double value;
    const char* expected;
  };
  for (const Case& c : {Case{kJs, -0.1, "Js = -0.1 kg m^2 must be > 0"}, Case{kJt, 0.5, "Jt = 0.5 kg m^2 must be > Js"},
                        Case{kFc1, -0.2, "fc1 = -0.2"}, Case{kFv1, -0.01, "fv1 = -0.01"}, Case{kFc2, -1.0, "fc2 = -1"},
                        Case{kFv2, -3.0, "fv2 = -3"}}) {
    ParamVector x = ok;
    x[c.index] = c.value;
    const std::vector<std::string> v = implausibilities(x);
    ASSERT_EQ(v.size(), 1u) << c.expected;
    EXPECT_NE(v[0].find(c.expected), std::string::npos) << v[0];
  }
}

TEST(Plausibility, NotEstimatedParametersAreNotChecked) {
  ParamVector x = toParamVector(defaultLeg());
  x[kFc1] = -1.0;
  x[kJt] = 0.0;
  EXPECT_EQ(implausibilities(x).size(), 2u);
  EXPECT_TRUE(implausibilities(x, {kMxt, kMyt, kJt, kFc1, kFv1}).empty());
}

TEST(Plausibility, NaNIsNeverPlausible) {
  ParamVector x = toParamVector(defaultLeg());
  x[kFv2] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(implausibilities(x).size(), 1u);
}

}  // namespace
}  // namespace exoid::ident
