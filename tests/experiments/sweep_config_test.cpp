// The sweep configuration: the checked-in default, and bad files failing with the key named.
#include "exoid/experiments/sweep_config.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace exoid::experiments {
namespace {

std::string writeToml(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name + ".toml";
  std::ofstream(path) << text;
  return path;
}

std::string errorOf(const std::string& name, const std::string& text) {
  try {
    loadSweepConfig(writeToml(name, text));
  } catch (const SweepConfigError& e) {
    return e.what();
  }
  return "no error";
}

TEST(SweepConfig, DefaultHasAtLeastAThousandIdentifications) {
  const SweepConfig c = loadSweepConfig(std::string(EXOID_SOURCE_DIR) + "/experiments/configs/default_sweep.toml");
  EXPECT_GE(c.seeds, 10);
  EXPECT_GE(static_cast<long>(c.numCells()) * c.seeds * static_cast<long>(c.methods.size()), 1000);
  EXPECT_EQ(c.methods.size(), allVariants().size());
}

TEST(SweepConfig, SeedsDependOnlyOnMasterSeedCellAndReplicate) {
  SweepConfig a, b;
  b.torque_noise_Nm = {7.0};  // another grid: same (cell, replicate) -> same seed
  EXPECT_EQ(a.jobSeed(3, 2), b.jobSeed(3, 2));
  EXPECT_NE(a.jobSeed(3, 2), a.jobSeed(2, 3));
  b.master_seed = 2;
  EXPECT_NE(a.jobSeed(3, 2), b.jobSeed(3, 2));
}

TEST(SweepConfig, BadFilesNameTheKeyAndLine) {
  const std::string unknown = errorOf("unknown", "[grid]\ntorque_noise_Nm = [0.5]\ntorque_nose = [1]\n");
  EXPECT_NE(unknown.find("grid.torque_nose"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("unknown.toml:3:"), std::string::npos) << unknown;
  const std::string type = errorOf("type", "[sweep]\nseeds = \"ten\"\n");
  EXPECT_NE(type.find("sweep.seeds"), std::string::npos) << type;
  EXPECT_NE(type.find("type.toml:2:"), std::string::npos) << type;
  const std::string empty = errorOf("empty", "[grid]\nvibration_level = []\n");
  EXPECT_NE(empty.find("grid.vibration_level"), std::string::npos) << empty;
  EXPECT_NE(empty.find("empty"), std::string::npos) << empty;
  const std::string negative = errorOf("negative", "[grid]\ntorque_noise_Nm = [0.0, -0.5]\n");
  EXPECT_NE(negative.find("grid.torque_noise_Nm"), std::string::npos) << negative;
  EXPECT_NE(negative.find("-0.5"), std::string::npos) << negative;
  const std::string method = errorOf("method", "[sweep]\nmethods = [\"ls\", \"magic\"]\n");
  EXPECT_NE(method.find("sweep.methods"), std::string::npos) << method;
  EXPECT_NE(method.find("magic"), std::string::npos) << method;
  const std::string section = errorOf("section", "[grids]\n");
  EXPECT_NE(section.find("grids"), std::string::npos) << section;
  const std::string syntax = errorOf("syntax", "[grid\n");
  EXPECT_NE(syntax.find("syntax.toml:1:"), std::string::npos) << syntax;
}

}  // namespace
}  // namespace exoid::experiments
