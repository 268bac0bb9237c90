#pragma once
// Shared test support for the sim module: a fixture that fails on any MuJoCo warning, inline
// models, and the tolerances (kept in one place, each with its reason).
#include "exoid/sim/mujoco_hooks.hpp"

#include <gtest/gtest.h>

#include <cstddef>
#include <string>

namespace exoid::sim::test {

/// Roundoff of sums of a few products of O(1) numbers (X from masses/lengths): ~1e-15;
/// the bound for "equals set B".
inline constexpr double kTruthTol = 1e-9;
/// Closing the loop analytically: roundoff of sin/cos/sqrt on 0.5 m lengths (~1e-16 m);
/// the bound at start is 1e-6 m.
inline constexpr double kLoopStartTol_m = 1e-6;
/// The bound during motion (solref 0.002 s gives ~5 um).
inline constexpr double kLoopMotionTol_m = 1e-4;

/// Fails a test if MuJoCo reported any warning while it ran.
class MujocoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    installMujocoHooks();
    warnings_at_start_ = mujocoWarningCount();
  }
  void TearDown() override {
    EXPECT_EQ(mujocoWarningCount(), warnings_at_start_)
        << "MuJoCo warned during the test: " << lastMujocoWarning();
  }

 private:
  std::size_t warnings_at_start_ = 0;
};

/// A writable scratch path under the test binary's working directory.
inline std::string scratchPath(const std::string& name) {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return std::string("sim_test_") + info->test_suite_name() + "_" + info->name() + "_" + name;
}

}  // namespace exoid::sim::test
