// The one file form of a Fourier trajectory: what is written reads back bit for bit (JSON numbers
// keep 17 digits), and what is wrong is named by its key.
#include "exoid/sim/trajectory_json.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace exoid::sim {
namespace {

core::FourierSeries threeJoints() {
  core::FourierSeries f = core::FourierSeries::still(3, 4, 0.1);
  f.offset_rad = Eigen::Vector3d(0.1, -0.2, 1.0 / 3.0);
  f.b_rad = Eigen::MatrixXd::Random(4, 3) * 0.1;
  f.a_rad = Eigen::MatrixXd::Random(4, 3) * 0.1;
  return f;
}

std::string errorOf(const nlohmann::json& j) {
  try {
    trajectoryFromJson(j);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(TrajectoryJson, ReadsBackWhatItWroteBitForBit) {
  core::FourierSeries f = threeJoints();
  const NamedTrajectory g = trajectoryFromJson(nlohmann::json::parse(trajectoryJson(f, {"hip", "knee", "ankle"}).dump()));
  EXPECT_EQ(g.joints, (std::vector<std::string>{"hip", "knee", "ankle"}));
  EXPECT_EQ(g.series.f0_hz, f.f0_hz);
  EXPECT_EQ(g.series.offset_rad, f.offset_rad);
  EXPECT_EQ(g.series.a_rad, f.a_rad);
  EXPECT_EQ(g.series.b_rad, f.b_rad);
  EXPECT_EQ(g.series.locked_joints, 0);
  // A locked joint (its harmonics zero) keeps its lock.
  f.a_rad.col(0).setZero();
  f.b_rad.col(0).setZero();
  f.locked_joints = 1;
  EXPECT_EQ(trajectoryFromJson(trajectoryJson(f, {"hip", "knee", "ankle"})).series.locked_joints, 1);
}

TEST(TrajectoryJson, WhatIsWrongIsNamedByItsKey) {
  const nlohmann::json good = trajectoryJson(threeJoints(), {"hip", "knee", "ankle"});
  nlohmann::json j = good;
  j["joints"][1].erase("cos_rad");
  EXPECT_NE(errorOf(j).find("joints[1].cos_rad is missing"), std::string::npos) << errorOf(j);
  j = good;
  j["joints"][2]["sin_rad"] = {0.1, 0.2};
  EXPECT_NE(errorOf(j).find("joints[2].sin_rad: 2 harmonics"), std::string::npos) << errorOf(j);
  j = good;
  j["joints"][0]["offset_rad"] = "zero";
  EXPECT_NE(errorOf(j).find("joints[0].offset_rad: expected a number"), std::string::npos) << errorOf(j);
  j = good;
  j["locked_joints"] = 7;
  EXPECT_NE(errorOf(j).find("locked_joints"), std::string::npos) << errorOf(j);
  j = good;
  j["locked_joints"] = 1;  // the hip locked, yet it moves
  EXPECT_NE(errorOf(j).find("locked"), std::string::npos) << errorOf(j);
  j = good;
  j["f0_hz"] = -1.0;
  EXPECT_NE(errorOf(j).find("f0_hz"), std::string::npos) << errorOf(j);
  j = good;
  j.erase("joints");
  EXPECT_NE(errorOf(j).find("joints is missing"), std::string::npos) << errorOf(j);
}

}  // namespace
}  // namespace exoid::sim
