#include "exoid/ident/metrics.hpp"

#include <gtest/gtest.h>

namespace exoid::ident {
namespace {

TEST(Metrics, TorqueErrorOfAKnownSample) {
  // |e| = 1, 2, 3, 4: mean 2.5, population std sqrt(1.25), rms sqrt(7.5), max 4.
  const Eigen::Vector4d measured(1.0, -2.0, 3.0, 0.0), predicted(0.0, 0.0, 0.0, 4.0);
  const TorqueErrorStats s = torqueError(measured, predicted);
  EXPECT_DOUBLE_EQ(s.mean_abs, 2.5);
  EXPECT_DOUBLE_EQ(s.std_abs, std::sqrt(1.25));
  EXPECT_DOUBLE_EQ(s.rms, std::sqrt(7.5));
  EXPECT_DOUBLE_EQ(s.max_abs, 4.0);
  EXPECT_THROW(torqueError(Eigen::Vector2d(1, 2), Eigen::Vector3d(1, 2, 3)), std::invalid_argument);
}

TEST(Metrics, ParameterErrorOfAKnownVector) {
  const Eigen::Vector3d truth(2.0, -4.0, 4.0), est(3.0, -4.0, 2.0);
  const ParamError e = paramError(est, truth);
  EXPECT_DOUBLE_EQ(e.abs[0], 1.0);
  EXPECT_DOUBLE_EQ(e.rel[0], 0.5);
  EXPECT_DOUBLE_EQ(e.rel[1], 0.0);
  EXPECT_DOUBLE_EQ(e.rel[2], -0.5);
  EXPECT_DOUBLE_EQ(e.norm_rel, std::sqrt(5.0) / 6.0);
  EXPECT_DOUBLE_EQ(e.max_abs_rel, 0.5);
  EXPECT_THROW(paramError(est, Eigen::Vector3d::Zero()), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::ident
