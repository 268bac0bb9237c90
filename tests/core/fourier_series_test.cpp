// The one trajectory type: analytic derivatives against differences of the angles, a fixed-size
// vector and a dynamic one give the same bits, and validation names what is wrong.
#include "exoid/core/fourier_series.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace exoid::core {
namespace {

FourierSeries twoJoints() {
  FourierSeries t = FourierSeries::still(2, 3, 0.2);
  t.offset_rad << -0.4, 0.9;
  t.a_rad << 0.1, -0.2, 0.05, 0.03, -0.02, 0.01;
  t.b_rad << 0.2, 0.1, -0.04, 0.06, 0.01, -0.02;
  return t;
}

TEST(FourierSeries, DerivativesMatchDifferencesOfTheAngles) {
  const FourierSeries t = twoJoints();
  const double h = 1e-4;
  for (double time : {0.0, 0.77, 3.1}) {
    Eigen::VectorXd q0, q1, q2, qd, qdd, dummy;
    t.at(time - h, q0, dummy, dummy);
    t.at(time, q1, qd, qdd);
    t.at(time + h, q2, dummy, dummy);
    // Central differences: error h^2 q''' / 6 ~ 1e-9 here.
    EXPECT_LT(((q2 - q0) / (2 * h) - qd).cwiseAbs().maxCoeff(), 1e-7);
    EXPECT_LT(((q2 - 2 * q1 + q0) / (h * h) - qdd).cwiseAbs().maxCoeff(), 1e-5);
  }
}

TEST(FourierSeries, FixedAndDynamicVectorsGiveTheSameBits) {
  const FourierSeries t = twoJoints();
  Eigen::Vector2d q2, qd2, qdd2;
  Eigen::VectorXd q, qd, qdd;
  for (double time : {0.0, 1.3, 4.99}) {
    t.at(time, q2, qd2, qdd2);
    t.at(time, q, qd, qdd);
    EXPECT_EQ(Eigen::VectorXd(q2), q);
    EXPECT_EQ(Eigen::VectorXd(qd2), qd);
    EXPECT_EQ(Eigen::VectorXd(qdd2), qdd);
  }
  // At t = 0 every phase is 0: q = offset + sum a.
  t.at(0.0, q, qd, qdd);
  EXPECT_DOUBLE_EQ(q[0], -0.4 + 0.1 + 0.05 - 0.02);
}

std::string errorOf(const FourierSeries& t) {
  try {
    t.validate();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

TEST(FourierSeries, ValidationNamesTheField) {
  EXPECT_EQ(errorOf(twoJoints()), "no error");
  FourierSeries t = twoJoints();
  t.f0_hz = 0.0;
  EXPECT_NE(errorOf(t).find("'f0_hz'"), std::string::npos);
  t = twoJoints();
  t.b_rad.resize(2, 2);
  EXPECT_NE(errorOf(t).find("'a_rad' and 'b_rad'"), std::string::npos);
  t = twoJoints();
  t.a_rad(1, 1) = std::nan("");
  EXPECT_NE(errorOf(t).find("NaN"), std::string::npos);
  t = twoJoints();
  t.locked_joints = 1;  // the hip moves
  EXPECT_NE(errorOf(t).find("joint 0 is locked"), std::string::npos);
  t.a_rad.col(0).setZero();
  t.b_rad.col(0).setZero();
  EXPECT_EQ(errorOf(t), "no error");
  t.locked_joints = 3;
  EXPECT_NE(errorOf(t).find("'locked_joints'"), std::string::npos);
  EXPECT_NE(errorOf(FourierSeries{}).find("no joints"), std::string::npos);
}

}  // namespace
}  // namespace exoid::core
