// Log profiles and flags: what a lab writes beside its logs, and what a wrong one is told.
#include "cli_test_support.hpp"
#include "exoid/experiments/protocol/log_input.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

namespace exoid::experiments {
namespace {

std::string write(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

std::string errorOf(const std::string& toml) {
  try {
    readLogProfile(write("profile_bad.toml", toml));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

TEST(LogProfile, ReadsColumnsUnitsSignsAndModel) {
  const LogInput in = readLogProfile(write("profile_ok.toml",
                                           "[columns]\nt = \"time\"\nq_hip = \"p1\"\n[units]\ntime = \"ms\"\nangle = \"deg\"\n"
                                           "[torque_sign]\nknee = -1\n[model]\nthigh_length_m = 0.3\n[sampling]\nmax_gap_ms = 8\n"));
  const auto mapped = [](const LogInput& li, const std::string& ours) {
    for (const auto& [o, theirs] : li.csv.format.columns) {
      if (o == ours) return theirs;
    }
    return std::string();
  };
  ASSERT_EQ(in.csv.format.columns.size(), 2u);
  EXPECT_EQ(mapped(in, "q_hip"), "p1");
  EXPECT_EQ(mapped(in, "t"), "time");
  EXPECT_DOUBLE_EQ(in.csv.format.time_scale_s, 1e-3);
  EXPECT_DOUBLE_EQ(in.csv.format.angle_scale_rad, M_PI / 180.0);
  EXPECT_EQ(in.csv.format.torque_sign[1], -1.0);
  EXPECT_DOUBLE_EQ(*in.thigh_length_m, 0.3);
  EXPECT_DOUBLE_EQ(in.csv.max_gap_s, 0.008);
  // Flags override the profile, name by name.
  LogInputFlags f;
  f.profile = ::testing::TempDir() + "/profile_ok.toml";
  f.columns = "q_hip=pos1";
  f.time_unit = "s";
  const LogInput over = resolveLogInput(f, 10.0);
  EXPECT_EQ(mapped(over, "q_hip"), "pos1");
  EXPECT_EQ(mapped(over, "t"), "time");
  EXPECT_DOUBLE_EQ(over.csv.format.time_scale_s, 1.0);
}

TEST(LogProfile, MistakesNameFileLineColumnAndKey) {
  const std::string unknown = errorOf("[columns]\nq_hips = \"p1\"\n");
  EXPECT_NE(unknown.find("profile_bad.toml:2:"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("q_hips"), std::string::npos) << unknown;
  const std::string unit = errorOf("[units]\ntime = \"min\"\n");
  EXPECT_NE(unit.find("units.time"), std::string::npos) << unit;
  EXPECT_NE(unit.find("s, ms or us"), std::string::npos) << unit;
  const std::string sign = errorOf("[torque_sign]\nhip = 2\n");
  EXPECT_NE(sign.find("1 or -1"), std::string::npos) << sign;
  const std::string key = errorOf("[model]\nthigh = 0.3\n");
  EXPECT_NE(key.find("unknown key"), std::string::npos) << key;
  const std::string syntax = errorOf("[columns\n");
  EXPECT_NE(syntax.find("profile_bad.toml:1:"), std::string::npos) << syntax;
}

TEST(LogProfile, ATimeColumnInMillisecondsIsPointedOut) {
  std::string csv = "# thigh_length_m: 0.45\nt,q_hip,q_knee,tau_hip,tau_knee\n";
  for (int i = 0; i < 2000; ++i) {
    csv += std::to_string(i) + "," + std::to_string(std::sin(i / 300.0)) + ",1," + std::to_string(std::cos(i / 200.0)) + ",2\n";
  }
  const std::string path = write("ms_time.csv", csv);
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  EXPECT_EQ(test::runExoid({"identify", "--data", path}), 1);
  testing::internal::GetCapturedStdout();
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("ms_time.csv"), std::string::npos) << err;
  EXPECT_NE(err.find("--time-unit"), std::string::npos) << err;
}

}  // namespace
}  // namespace exoid::experiments
