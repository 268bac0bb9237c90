// A chain out of a robot's tree (a whole-body exoskeleton URDF, a published quadruped) in every command
// that simulates: simulate, sweep and reproduce take identify's --base, --tip and --lock
// JOINT=VALUE (a sweep's [sweep] base, tip, lock), so the user's leg inside a whole-body file is
// simulated, swept and identified as one chain; what cannot take them is refused by name.
#include "cli_test_support.hpp"
#include "exoid/experiments/sweep/sweep_config.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

// Named, not anonymous: the unity build puts this file beside the other CLI tests' helpers.
namespace exoid::experiments::tree_chain_tests {

using exoid::test::readJson;
using exoid::test::runExoid;
using exoid::test::slurp;

const std::string kExo = std::string(EXOID_SOURCE_DIR) + "/tests/data/two_leg_exo.urdf";

std::string tempPath(const std::string& name) { return ::testing::TempDir() + "/tree_chain_" + std::to_string(::getpid()) + "_" + name; }

// The exit code and standard error of `exoid args...` (its standard output dropped).
std::pair<int, std::string> exoidFailing(const std::vector<std::string>& args) {
  testing::internal::CaptureStderr();
  testing::internal::CaptureStdout();
  const int code = runExoid(args);
  testing::internal::GetCapturedStdout();
  return {code, testing::internal::GetCapturedStderr()};
}

// The worst |b[key] - truth| / max(1, |truth|) over the base parameters of identify's JSON.
double worstRelativeError(const nlohmann::json& fit, const char* key) {
  const nlohmann::json& b = fit["base_parameters"];
  double worst = 0.0;
  for (std::size_t i = 0; i < b["names"].size(); ++i) {
    const double truth = b["truth"][i], value = b[key][i];
    worst = std::max(worst, std::abs(value - truth) / std::max(1.0, std::abs(truth)));
  }
  return worst;
}

// The left leg from the pelvis to the shank, its ankle held at a posture: exact data on the rigid
// stand give every base parameter to rounding (measured: 6.6e-13 relative), and the simulated
// bodies are the ones identify reads with the same options (the held ankle and foot lumped into
// the shank): its CAD is the truth to MuJoCo's inertia round trip (3.4e-7, urdf_rig_test), and
// another posture of the ankle (another lumped shank) is not, while the fit, which takes only the
// chain's kinematics from the file, stays exact.
TEST(TreeChainCli, ALegOutOfAWholeBodyUrdfIsSimulatedAndIdentifiedExactly) {
  const std::string csv = tempPath("leg.csv"), side = tempPath("leg.json"), fit = tempPath("fit.json"), other = tempPath("other.json");
  const std::vector<std::string> chain = {"--base", "pelvis", "--tip", "l_shank", "--lock", "l_ankle_pitch=0.1", "--lock", "l_ankle_roll=-0.05"};
  std::vector<std::string> simulate = {"simulate", "--model", kExo, "--duration", "5", "--coulomb-v0", "0", "--record-derivatives", "--out", csv};
  simulate.insert(simulate.end(), chain.begin(), chain.end());
  std::vector<std::string> identify = {"identify", "--model", kExo, "--data", csv, "--truth", side, "--json", fit};
  identify.insert(identify.end(), chain.begin(), chain.end());
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid(simulate), 0);
  ASSERT_EQ(runExoid(identify), 0);
  // The ankle held at another posture: another lumped shank, not the simulated one.
  std::vector<std::string> elsewhere = identify;
  std::replace(elsewhere.begin(), elsewhere.end(), std::string("l_ankle_pitch=0.1"), std::string("l_ankle_pitch=0.3"));
  std::replace(elsewhere.begin(), elsewhere.end(), fit, other);
  EXPECT_EQ(runExoid(elsewhere), 0);
  testing::internal::GetCapturedStdout();

  const nlohmann::json s = readJson(side);
  EXPECT_EQ(s["model"]["joints"], (std::vector<std::string>{"l_hip_yaw", "l_hip_roll", "l_hip_pitch", "l_knee"}));
  EXPECT_EQ(s["model"]["selection"], "--base pelvis --tip l_shank --lock l_ankle_pitch=0.1 --lock l_ankle_roll=-0.05");
  const nlohmann::json same = readJson(fit), moved = readJson(other);
  EXPECT_LT(worstRelativeError(same, "ls"), 1e-9);
  EXPECT_LT(worstRelativeError(same, "cad"), 1e-6);
  EXPECT_LT(worstRelativeError(moved, "ls"), 1e-9);
  EXPECT_GT(worstRelativeError(moved, "cad"), 1e-3);
}

// The same joints held at another posture move otherwise: a record (and its truth) simulated with
// the knee held at 0.8 rad, read as the chain with it held at 0, or not held at all, is refused,
// naming the record's selection and the one given (before: exit 0, its truth 62 % off in
// foot.mz). The record's own selection, or a branch held elsewhere (the test above), passes.
TEST(TreeChainCli, DataOfAnotherChainOfTheFileAreRefusedNamingBothSelections) {
  const std::string urdf = std::string(EXOID_SOURCE_DIR) + "/models/leg3.urdf";
  const std::string csv = tempPath("held_knee.csv"), side = tempPath("held_knee.json");
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"simulate", "--model", urdf, "--lock", "knee=0.8", "--duration", "4", "--out", csv}), 0);
  EXPECT_EQ(runExoid({"identify", "--model", urdf, "--lock", "knee=0.8", "--data", csv, "--truth", side}), 0);
  testing::internal::GetCapturedStdout();
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"identify", "--model", urdf, "--lock", "knee=0", "--data", csv},
        std::vector<std::string>{"identifiability", "--model", urdf, "--lock", "knee=0", "--data", csv}}) {
    auto [code, err] = exoidFailing(args);
    EXPECT_EQ(code, 1) << args[0];
    EXPECT_NE(err.find(csv + " (metadata 'chain_selection'): data of the chain '--lock knee=0.8'"), std::string::npos) << err;
    EXPECT_NE(err.find("read as '--lock knee=0', which differ in joint ankle's placement"), std::string::npos) << err;
  }
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"simulate", "--model", urdf, "--duration", "1", "--out", tempPath("unheld.csv")}), 0);
  testing::internal::GetCapturedStdout();
  auto [code, err] = exoidFailing({"identify", "--model", urdf, "--data", tempPath("unheld.csv"), "--truth", side});
  EXPECT_EQ(code, 1);
  EXPECT_NE(err.find("(model.selection): data of the chain '--lock knee=0.8'"), std::string::npos) << err;
  EXPECT_NE(err.find("read as 'none', which differ in its joints (hip, ankle)"), std::string::npos) << err;
}

// A leg of a published legged robot nobody here wrote (tests/data/solo12, BSD-3-Clause), from
// exact data: LS is the truth to rounding, and the consistent fit says a physical body explains it
// (before, its search stalled short of LS and the leg was reported 2.44e6 standard errors from any
// consistent body, exit 3, as 8 of 11 such descriptions were).
TEST(TreeChainCli, APublishedRobotsLegIsIdentifiedExactlyAndConsistent) {
  const std::string urdf = std::string(EXOID_SOURCE_DIR) + "/tests/data/solo12/solo12.urdf";
  const std::string csv = tempPath("solo12.csv"), side = tempPath("solo12.json"), fit = tempPath("solo12_fit.json");
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"simulate", "--model", urdf, "--tip", "HL_FOOT", "--duration", "5", "--coulomb-v0", "0", "--record-derivatives", "--out", csv}), 0);
  EXPECT_EQ(runExoid({"identify", "--model", urdf, "--tip", "HL_FOOT", "--data", csv, "--truth", side, "--json", fit}), 0);
  testing::internal::GetCapturedStdout();
  const nlohmann::json j = readJson(fit);
  EXPECT_EQ(j["problems"].size(), 0u) << j["problems"].dump();
  EXPECT_EQ(j["consistent"]["status"], "least_squares_consistent") << j["consistent"].dump();
  EXPECT_LT(worstRelativeError(j, "ls"), 1e-9);
}

TEST(TreeChainCli, WhatCannotChooseAChainIsRefusedNamingTheOptions) {
  const std::string csv = tempPath("refused.csv");
  // A tree without its chain: the leaves to choose a --tip from.
  auto [code, err] = exoidFailing({"simulate", "--model", kExo, "--out", csv});
  EXPECT_NE(code, 0);
  EXPECT_NE(err.find("--tip"), std::string::npos) << err;
  EXPECT_NE(err.find("l_sole"), std::string::npos) << err;
  // An MJCF is simulated as it is; the APAL leg's rig and protocol are their own.
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"simulate", "--model", "leg3", "--tip", "shank", "--out", csv},
        std::vector<std::string>{"simulate", "--base", "trunk", "--out", csv},
        std::vector<std::string>{"reproduce", "--model", "leg3", "--lock", "ankle=0", "--out", tempPath("refused_reproduce")},
        std::vector<std::string>{"reproduce", "--tip", "shank", "--out", tempPath("refused_reproduce")}}) {
    std::tie(code, err) = exoidFailing(args);
    EXPECT_NE(code, 0) << args[0] << " " << args[2];
    EXPECT_NE(err.find("--base/--tip/--lock"), std::string::npos) << err;
    EXPECT_NE(err.find("URDF's tree"), std::string::npos) << err;
  }
  EXPECT_FALSE(std::filesystem::exists(csv));
  // simulate's --lock takes both: JOINT (the rig's lock) and JOINT=VALUE (the tree's), checked.
  std::tie(code, err) = exoidFailing({"simulate", "--model", kExo, "--tip", "l_foot", "--lock", "strap_slider=x", "--out", csv});
  EXPECT_NE(code, 0);
  EXPECT_NE(err.find("expected JOINT=VALUE"), std::string::npos) << err;
}

std::string writeToml(const std::string& name, const std::string& text) {
  const std::string path = tempPath(name + ".toml");
  std::ofstream(path) << text;
  return path;
}

std::string sweepConfigError(const std::string& text) {
  try {
    loadSweepConfig(writeToml("bad", text));
  } catch (const SweepConfigError& e) {
    return e.what();
  }
  return "no error";
}

// A sweep of the leg out of the whole body, across vibration levels: a cell per level, the chain
// as selected in every run and in config.json (a resume or a shard elsewhere matches it).
TEST(TreeChainSweep, ALegOutOfAWholeBodyUrdfIsSweptAcrossVibration) {
  const std::string dir = tempPath("sweep");
  std::filesystem::remove_all(dir);
  const std::string cfg = writeToml("sweep", "[sweep]\nmodel = \"" + kExo + "\"\nbase = \"pelvis\"\ntip = \"l_shank\"\n"
                                             "lock = [\"l_ankle_pitch=0.1\", \"l_ankle_roll=0\"]\nseeds = 1\nmethods = [\"ls\"]\n"
                                             "[grid]\ntorque_noise_Nm = [0.1]\nvibration_level = [0.0, 1.0]\ntrajectories = [\"default\"]\n"
                                             "[simulation]\nduration_s = 3.0\n");
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"sweep", "--config", cfg, "--out", dir}), 0);
  testing::internal::GetCapturedStdout();
  const nlohmann::json config = readJson(dir + "/config.json");
  EXPECT_EQ(config["sweep"]["selection"], "--base pelvis --tip l_shank --lock l_ankle_pitch=0.1 --lock l_ankle_roll=0");
  const nlohmann::json summary = readJson(dir + "/summary.json");
  ASSERT_EQ(summary["conditions"].size(), 2u);
  for (const nlohmann::json& c : summary["conditions"]) {
    EXPECT_EQ(c["methods"]["ls"]["n"], 1) << c.dump();
    EXPECT_EQ(c["base_parameters"]["names"].size(), 30u) << c.dump();  // the 4-joint chain's, as identify --model reads it
  }

  std::string e = sweepConfigError("[sweep]\nmodel = \"leg3\"\ntip = \"shank\"\n");
  EXPECT_NE(e.find("'sweep.tip'"), std::string::npos) << e;
  EXPECT_NE(e.find("MJCF"), std::string::npos) << e;
  e = sweepConfigError("[sweep]\nbase = \"pelvis\"\n");
  EXPECT_NE(e.find("'sweep.base'"), std::string::npos) << e;
  e = sweepConfigError("[sweep]\nmodel = \"" + kExo + "\"\nlock = [\"l_knee\"]\n");
  EXPECT_NE(e.find("'sweep.lock'"), std::string::npos) << e;
  EXPECT_NE(e.find("JOINT=VALUE"), std::string::npos) << e;
  e = sweepConfigError("[sweep]\nmodel = \"" + kExo + "\"\n");
  EXPECT_NE(e.find("[sweep] base, tip, lock"), std::string::npos) << e;
}

}  // namespace exoid::experiments::tree_chain_tests
