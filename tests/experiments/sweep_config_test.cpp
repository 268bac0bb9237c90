// The sweep configuration: the checked-in default, and bad files failing with the key named.
#include "exoid/experiments/sweep/sweep_config.hpp"
#include "exoid/experiments/sweep/sweep_summary.hpp"

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

// The trajectory axis: optimised cells use the designs, share their seeds with their paper twins
// (so the comparison pairs), and a level without designs is refused naming the key.
TEST(SweepConfig, TrajectoryAxisPairsOptimisedCellsWithTheirPaperTwins) {
  const std::string dir = std::string(EXOID_SOURCE_DIR) + "/experiments/configs/";
  const std::string path = writeToml("traj", "[grid]\ntorque_noise_Nm = [0.1, 0.5]\nvibration_level = [1.0]\n"
                                             "cylinder_mass_scale = [1.0]\ntrajectories = [\"paper\", \"optimised\"]\n"
                                             "[simulation]\nexcitation_knee = \"" + dir + "excitation_knee.json\"\n"
                                             "excitation_both = \"" + dir + "excitation_both.json\"\n");
  const SweepConfig c = loadSweepConfig(path);
  const std::vector<SweepCondition> conds = c.conditions();
  ASSERT_EQ(conds.size(), 4u);
  for (int k = 0; k < 2; ++k) {
    const auto K = static_cast<std::size_t>(k);
    EXPECT_EQ(conds[K].trajectories, "paper");
    EXPECT_EQ(conds[K + 2].trajectories, "optimised");
    EXPECT_EQ(conds[K].torque_noise_Nm, conds[K + 2].torque_noise_Nm);
    EXPECT_EQ(c.jobSeed(k, 5), c.jobSeed(k + 2, 5));  // common random numbers
    EXPECT_FALSE(c.protocolFor(conds[K], 1).both_excitation.has_value());
    EXPECT_TRUE(c.protocolFor(conds[K + 2], 1).both_excitation.has_value());
    EXPECT_TRUE(c.protocolFor(conds[K + 2], 1).knee_excitation.has_value());
  }
  EXPECT_NE(c.jobSeed(0, 5), c.jobSeed(1, 5));
  EXPECT_TRUE(c.toJson()["simulation"].contains("excitation_both"));

  const std::string missing = errorOf("nodesign", "[grid]\ntrajectories = [\"paper\", \"optimised\"]\n");
  EXPECT_NE(missing.find("grid.trajectories"), std::string::npos) << missing;
  EXPECT_NE(missing.find("excitation_knee"), std::string::npos) << missing;
  const std::string bad = errorOf("badtraj", "[grid]\ntrajectories = [\"designed\"]\n");
  EXPECT_NE(bad.find("grid.trajectories"), std::string::npos) << bad;
  EXPECT_NE(bad.find("designed"), std::string::npos) << bad;
}

// The encoder-backlash axis (docs/findings.md 4.1: the source of the real logs' bias): each level
// reaches the simulator's sensors and the job's recorded condition; one level of 0 (the default)
// leaves the cells and their seeds as they were; a play outside [0, 89] deg is refused by key.
TEST(SweepConfig, EncoderBacklashAxisReachesTheSimulatorAndKeepsTheOtherCellsSeeds) {
  const std::string grid = "[grid]\ntorque_noise_Nm = [0.1, 0.5]\nvibration_level = [1.0]\ncylinder_mass_scale = [1.0]\n";
  const SweepConfig none = loadSweepConfig(writeToml("play0", grid));
  const SweepConfig play = loadSweepConfig(writeToml("play", grid + "encoder_backlash_deg = [0.0, 0.1]\n"));
  ASSERT_EQ(none.numCells(), 2);
  ASSERT_EQ(play.numCells(), 4);
  const std::vector<SweepCondition> conds = play.conditions();
  for (int k = 0; k < 4; ++k) {
    const SweepCondition& c = conds[static_cast<std::size_t>(k)];
    EXPECT_EQ(c.encoder_backlash_deg, k < 2 ? 0.0 : 0.1);
    EXPECT_EQ(play.protocolFor(c, 1).sim.sensors.encoder_backlash_deg, c.encoder_backlash_deg);
    EXPECT_EQ(toJson(c).at("encoder_backlash_deg").get<double>(), c.encoder_backlash_deg);
    if (k < 2) {
      EXPECT_EQ(play.jobSeed(k, 3), none.jobSeed(k, 3));
      EXPECT_EQ(c.torque_noise_Nm, none.conditions()[static_cast<std::size_t>(k)].torque_noise_Nm);
    }
  }
  EXPECT_EQ(play.toJson().at("grid").at("encoder_backlash_deg"), nlohmann::json::array({0.0, 0.1}));
  // No play: config.json as before the axis, so a folder started then resumes.
  EXPECT_FALSE(none.toJson().at("grid").contains("encoder_backlash_deg"));
  EXPECT_EQ(layoutFromJson(play.toJson()).cells.size(), 4u);
  EXPECT_EQ(layoutFromJson(none.toJson()).cells.size(), 2u);
  const std::string wide = errorOf("play_wide", "[grid]\nencoder_backlash_deg = [90.0]\n");
  EXPECT_NE(wide.find("grid.encoder_backlash_deg"), std::string::npos) << wide;
  const std::string negative = errorOf("play_negative", "[grid]\nencoder_backlash_deg = [-0.1]\n");
  EXPECT_NE(negative.find("grid.encoder_backlash_deg"), std::string::npos) << negative;
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

// The 'default' arm's base-motion terms: unset keeps identify's (and the config JSON as before);
// set, it is recorded; a word identify does not take is refused with the key and line.
TEST(SweepConfig, BaseTermsReachTheDefaultArmAndTheConfigRecord) {
  const SweepConfig plain = loadSweepConfig(writeToml("base_plain", "[grid]\ntorque_noise_Nm = [0.5]\n"));
  EXPECT_FALSE(plain.base.default_base_terms.has_value());
  EXPECT_FALSE(plain.toJson().contains("default_base_terms"));
  const SweepConfig judged = loadSweepConfig(writeToml("base_judged", "[identification]\nbase_terms = \"judged\"\n"));
  ASSERT_TRUE(judged.base.default_base_terms.has_value());
  EXPECT_EQ(*judged.base.default_base_terms, ident::BaseTerms::kJudged);
  EXPECT_EQ(judged.toJson()["default_base_terms"], "judged");
  const std::string bad = errorOf("base_bad", "[identification]\nbase_terms = \"sometimes\"\n");
  EXPECT_NE(bad.find("identification.base_terms"), std::string::npos) << bad;
  EXPECT_NE(bad.find("base_bad.toml:2:"), std::string::npos) << bad;
}

}  // namespace
}  // namespace exoid::experiments
