// The segmental strategy's physical consistency: the nearest consistent estimate in the metric of
// its reported covariance, and violations judged in its reported errors, as one fit's are.
#include "exoid/experiments/protocol/identification.hpp"

#include "exoid/ident/leg/params.hpp"

#include <gtest/gtest.h>

namespace exoid::experiments {
namespace {

// A segmental LS outcome of the default leg's X with independent reported errors of 1 % of each
// parameter (at least 1e-3).
MethodOutcome segmentalOutcome(const ident::ParamVector& x) {
  MethodOutcome m;
  m.x = x;
  ident::ReportedErrors e;
  e.reported = x.cwiseAbs().cwiseMax(0.1) * 0.01;
  e.newey_west = e.reported;
  e.jackknife = e.reported;
  e.from_jackknife.assign(ident::kNumParams, false);
  e.covariance = e.reported.cwiseAbs2().asDiagonal();
  m.segmental_errors = e;
  return m;
}

TEST(SegmentalConsistency, AConsistentEstimateIsLeftExactlyAsItIs) {
  const ident::ParamVector x = ident::toParamVector(ident::defaultLeg());
  MethodOutcome m = segmentalOutcome(x);
  applySegmentalConsistency(m, ident::LegConstants{});
  ASSERT_TRUE(m.consistency.has_value());
  EXPECT_FALSE(m.consistency->fit.constrained);
  EXPECT_EQ(m.x, x);
  EXPECT_TRUE(m.implausible.empty());
}

// fv2 below zero by `sigmas` of its reported error. With independent errors the nearest consistent
// point in their metric moves fv2 alone, onto its bound.
TEST(SegmentalConsistency, AViolationWithinTheSignificanceIsMovedOntoItsBoundAndIsNotAProblem) {
  ident::ParamVector x = ident::toParamVector(ident::defaultLeg());
  MethodOutcome m = segmentalOutcome(x);
  const double se = m.segmental_errors->reported[ident::kFv2];
  x[ident::kFv2] = -1.0 * se;
  m.x = x;
  applySegmentalConsistency(m, ident::LegConstants{});
  ASSERT_TRUE(m.consistency.has_value());
  EXPECT_TRUE(m.consistency->fit.constrained);
  EXPECT_TRUE(m.implausible.empty());
  ASSERT_EQ(m.consistency->withinNoise().size(), 1u);
  EXPECT_NE(m.consistency->withinNoise().front().find("fv2 >= 0"), std::string::npos);
  // The interior point stops within its gap tolerance (1e-14 of the cost): far below 1e-6 errors.
  EXPECT_GE(m.x[ident::kFv2], 0.0);
  EXPECT_LT(m.x[ident::kFv2], 1e-6 * se);
  for (int i = 0; i < ident::kNumParams; ++i) {
    if (i == ident::kFv2) continue;
    EXPECT_NEAR(m.x[i], x[i], 1e-6 * m.segmental_errors->reported[i]) << ident::paramName(i);
  }
  EXPECT_EQ(m.consistency->unconstrained, Eigen::VectorXd(x));
}

TEST(SegmentalConsistency, AViolationBeyondTheSignificanceStaysAProblemNamingItsSize) {
  ident::ParamVector x = ident::toParamVector(ident::defaultLeg());
  MethodOutcome m = segmentalOutcome(x);
  x[ident::kFv2] = -5.0 * m.segmental_errors->reported[ident::kFv2];
  m.x = x;
  applySegmentalConsistency(m, ident::LegConstants{});
  ASSERT_EQ(m.implausible.size(), 1u);
  EXPECT_NE(m.implausible.front().find("fv2 >= 0 violated by 5 standard errors"), std::string::npos) << m.implausible.front();
}

TEST(SegmentalConsistency, NeedsTheSegmentalErrors) {
  MethodOutcome m;
  EXPECT_THROW(applySegmentalConsistency(m, ident::LegConstants{}), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::experiments
