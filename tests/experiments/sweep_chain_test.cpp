// `exoid sweep --model`: a chain model's sweep. Its configuration refuses what the chain rig
// lacks, naming the key; its runs are scored against the model's truth and summarised with
// statistics a test recomputes from the run records; threads, shards + merge and resume give the
// same bytes.
#include "exoid/experiments/commands/robot_commands.hpp"
#include "exoid/experiments/protocol/excitation_design.hpp"
#include "exoid/experiments/protocol/robot_loader.hpp"
#include "exoid/experiments/sweep/robot_sweep.hpp"
#include "exoid/experiments/sweep/sweep_config.hpp"
#include "sweep_test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

// Named, not anonymous: the unity build puts this file beside the other sweep tests' helpers.
namespace exoid::experiments::sweep_chain_tests {

using test::expectSameSweep;
using test::freshDir;
using test::runExoid;
using test::slurp;

std::string writeToml(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/chain_sweep_" + std::to_string(::getpid()) + "_" + name + ".toml";
  std::ofstream(path) << text;
  return path;
}

std::string chainConfigError(const std::string& text, const std::string& model = "") {
  try {
    loadSweepConfig(writeToml("bad", text), model);
  } catch (const SweepConfigError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ChainSweepConfig, AModelGivesTheChainsGridAndMethods) {
  const SweepConfig c = loadSweepConfig(writeToml("leg3", "[sweep]\nmodel = \"leg3\"\n"));
  ASSERT_TRUE(c.isChain());
  EXPECT_EQ(c.vibration_level, std::vector<double>{0.0});
  EXPECT_EQ(c.cylinder_mass_scale, std::vector<double>{0.0});
  EXPECT_EQ(c.trajectories, std::vector<std::string>{"optimised"});
  EXPECT_EQ(c.methodNames(), (std::vector<std::string>{"ls", "rls", "pso", "rls-pso", "lad", "iv-band", "idim-iv"}));
  EXPECT_EQ(c.numCells(), static_cast<int>(c.torque_noise_Nm.size()));
  // The shipped chain grid, and --model on it.
  const SweepConfig shipped = loadSweepConfig(std::string(EXOID_SOURCE_DIR) + "/experiments/configs/robot_sweep.toml");
  EXPECT_TRUE(shipped.isChain());
  EXPECT_EQ(shipped.trajectories, (std::vector<std::string>{"optimised", "default"}));
  // The APAL leg's sweep is as before: no model in its resolved configuration (old folders resume).
  const SweepConfig apal = loadSweepConfig(std::string(EXOID_SOURCE_DIR) + "/experiments/configs/default_sweep.toml");
  EXPECT_FALSE(apal.isChain());
  EXPECT_FALSE(apal.toJson()["sweep"].contains("model"));
  EXPECT_FALSE(loadSweepConfig(writeToml("apal", "[sweep]\nmodel = \"apal\"\n")).isChain());
}

TEST(ChainSweepConfig, RefusesWhatTheChainRigLacksNamingTheKey) {
  const std::string leg3 = "[sweep]\nmodel = \"leg3\"\n";
  // leg3 stands on a compliant mount and its encoders have play, as the APAL leg's.
  EXPECT_EQ(chainConfigError(leg3 + "[grid]\nvibration_level = [0.0, 1.0]\nencoder_backlash_deg = [0.0, 0.1]\n"), "no error");
  // A model without mount joints has no vibration to scale.
  std::ifstream in(std::string(EXOID_SOURCE_DIR) + "/models/leg3.xml");
  std::string xml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (std::size_t at; (at = xml.find("<joint name=\"mount_")) != std::string::npos;) xml.erase(at, xml.find("/>", at) + 2 - at);
  const std::string rigid = ::testing::TempDir() + "/rigid_leg3_" + std::to_string(::getpid()) + ".xml";
  std::ofstream(rigid) << xml;
  std::string e = chainConfigError("[sweep]\nmodel = \"" + rigid + "\"\n[grid]\nvibration_level = [0.0, 1.0]\n");
  EXPECT_NE(e.find("'grid.vibration_level'"), std::string::npos) << e;
  EXPECT_NE(e.find("rigid stand"), std::string::npos) << e;
  e = chainConfigError(leg3 + "[grid]\ncylinder_mass_scale = [1.0]\n");
  EXPECT_NE(e.find("'grid.cylinder_mass_scale'"), std::string::npos) << e;
  e = chainConfigError(leg3 + "[grid]\ntrajectories = [\"paper\"]\n");
  EXPECT_NE(e.find("'grid.trajectories'"), std::string::npos) << e;
  EXPECT_NE(e.find("\"default\""), std::string::npos) << e;
  EXPECT_EQ(chainConfigError("[sweep]\nmethods = [\"ls\", \"idim-iv\"]\nmodel = \"leg3\"\n"), "no error");  // the rig's controller is in its records
  e = chainConfigError("[sweep]\nmethods = [\"ls-exact\"]\nmodel = \"leg3\"\n");
  EXPECT_NE(e.find("iv-band"), std::string::npos) << e;  // names the chain's methods
  e = chainConfigError(leg3 + "[simulation]\nramp_s = 1.0\n");
  EXPECT_NE(e.find("'simulation.ramp_s'"), std::string::npos) << e;
  // A URDF's chain is simulated on the stand (sim/urdf_rig.hpp): vibration is an axis of its sweep.
  EXPECT_EQ(chainConfigError("[sweep]\nmodel = \"" + std::string(EXOID_SOURCE_DIR) + "/models/leg3.urdf\"\n[grid]\nvibration_level = [0.0, 1.0]\n"),
            "no error");
  e = chainConfigError("[sweep]\nmodel = \"no_such_model.xml\"\n");
  EXPECT_NE(e.find("'sweep.model'"), std::string::npos) << e;
  EXPECT_NE(e.find("no_such_model.xml"), std::string::npos) << e;
  e = chainConfigError("[simulation]\nexcitation = \"x.json\"\n");
  EXPECT_NE(e.find("'simulation.excitation'"), std::string::npos) << e;
  // A design of another model (two joints for leg3's three) is refused before any run, by key.
  const std::string two = ::testing::TempDir() + "/chain_sweep_two_joints.json";
  std::ofstream(two) << R"({"trajectory": {"f0_hz": 0.2, "locked_joints": 0,
                                            "joints": [{"name": "a", "offset_rad": 0, "cos_rad": [0.1], "sin_rad": [0.1]},
                                                       {"name": "b", "offset_rad": 0, "cos_rad": [0.1], "sin_rad": [0.1]}]}})";
  e = chainConfigError(leg3 + "[simulation]\nexcitation = \"" + two + "\"\n");
  EXPECT_NE(e.find("'simulation.excitation'"), std::string::npos) << e;
  EXPECT_NE(e.find("moves 2 joints (a, b)"), std::string::npos) << e;
  EXPECT_NE(e.find("hip, knee, ankle"), std::string::npos) << e;
  // --model on the APAL leg's grid: its APAL-only methods are refused by name.
  e = chainConfigError("[sweep]\nmethods = [\"ls\", \"idim-iv-base\"]\n", "leg3");
  EXPECT_NE(e.find("'sweep.methods'"), std::string::npos) << e;
}

// A quick design (one restart) for the "optimised" level, written once per process.
const std::string& designFile() {
  static const std::string path = [] {
    ExciteRequest ex;
    ex.model = "leg3";
    ex.out = ::testing::TempDir() + "/chain_sweep_design_" + std::to_string(::getpid()) + ".json";
    ex.options.restarts = 1;
    ex.options.max_evaluations = 400;
    ex.plot = false;
    excite(ex);
    return ex.out;
  }();
  return path;
}

std::string tinyChainConfig() {
  return writeToml("tiny", "[sweep]\nmodel = \"leg3\"\nseeds = 2\nmethods = [\"ls\", \"lad\", \"idim-iv\"]\n"
                           "[grid]\ntorque_noise_Nm = [0.0, 0.5]\ntrajectories = [\"optimised\", \"default\"]\n"
                           "[simulation]\nduration_s = 4.0\nexcitation = \"" + designFile() + "\"\n");
}

const std::string& referenceChainSweep() {
  static const std::string dir = [] {
    const std::string d = freshDir("chain_reference");
    EXPECT_EQ(runExoid({"sweep", "--config", tinyChainConfig(), "--out", d, "--threads", "2"}), 0);
    return d;
  }();
  return dir;
}

double medianOf(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t h = v.size() / 2;
  return v.size() % 2 ? v[h] : 0.5 * (v[h - 1] + v[h]);
}

// The summary's statistics, recomputed here from the run records, and the truth from the model.
TEST(ChainSweep, ScoresEveryRunAgainstTheModelsTruth) {
  const std::string& d = referenceChainSweep();
  const LoadedChain leg3 = loadChain("leg3");
  const Eigen::VectorXd truth = leg3.base.combination * leg3.phi;
  const nlohmann::json summary = exoid::test::readJson(d + "/summary.json");
  ASSERT_EQ(summary["conditions"].size(), 4u);
  std::map<int, std::vector<double>> ls_median;  // cell -> per seed
  std::map<int, std::vector<double>> ls_z;       // cell -> sum over seeds of z = error / se, per parameter
  std::map<int, std::vector<int>> ls_held;       // cell -> seeds whose x -+ 1.96 se held the truth, per parameter
  for (const auto& e : std::filesystem::directory_iterator(d + "/runs")) {
    const nlohmann::json j = exoid::test::readJson(e.path().string());
    ASSERT_EQ(j["status"], "ok") << j["message"];
    const std::vector<double> t = j["truth"];
    ASSERT_EQ(static_cast<Eigen::Index>(t.size()), truth.size());
    for (Eigen::Index i = 0; i < truth.size(); ++i) EXPECT_NEAR(t[static_cast<std::size_t>(i)], truth[i], 1e-12 * (1.0 + std::abs(truth[i])));
    EXPECT_EQ(j["base_parameters"].get<std::vector<std::string>>(), leg3.base.names);
    ASSERT_EQ(j["methods"].size(), 3u);
    const nlohmann::json& ls = j["methods"][0];
    ASSERT_EQ(ls["method"], "ls");
    const std::vector<double> x = ls["x"], se = ls["std_error"];
    double scale = 0.0;
    for (double v : t) scale = std::max(scale, std::abs(v));
    std::vector<double> rel;
    std::vector<double>& z = ls_z[j["cell"]];
    z.resize(t.size(), 0.0);
    std::vector<int>& held = ls_held[j["cell"]];
    held.resize(t.size(), 0);
    for (std::size_t i = 0; i < t.size(); ++i) {
      if (std::abs(t[i]) > 1e-12 * scale) rel.push_back(std::abs(x[i] - t[i]) / std::abs(t[i]));
      if (se[i] > 0.0) z[i] += (x[i] - t[i]) / se[i];
      held[i] += std::abs(x[i] - t[i]) <= 1.959963984540054 * se[i] ? 1 : 0;
    }
    ls_median[j["cell"]].push_back(medianOf(rel));
  }
  for (const nlohmann::json& c : summary["conditions"]) {
    const int cell = c["cell"];
    const nlohmann::json& ls = c["methods"]["ls"];
    const std::vector<double>& m = ls_median[cell];
    ASSERT_EQ(m.size(), 2u);
    EXPECT_NEAR(ls["metrics"]["median_abs_rel_err"]["mean"].get<double>(), 0.5 * (m[0] + m[1]), 1e-15);
    for (std::size_t i = 0; i < leg3.base.names.size(); ++i) {
      const nlohmann::json& p = ls["parameters"][leg3.base.names[i]];
      EXPECT_EQ(p["coverage95"]["n"], 0);  // a chain's runs give no CRB
      const nlohmann::json& k = p["coverage95_reported"];
      if (k["n"] == 0) continue;  // a noise-free cell's zero standard errors give no interval
      EXPECT_EQ(k["n"], 2);
      EXPECT_DOUBLE_EQ(k["share"].get<double>(), ls_held[cell][i] / 2.0) << leg3.base.names[i];
      EXPECT_NEAR(k["mean_error_over_sigma"].get<double>(), ls_z[cell][i] / 2.0, 1e-12 * (1.0 + std::abs(ls_z[cell][i]))) << leg3.base.names[i];
    }
    EXPECT_TRUE(c["methods"]["lad"].contains("vs_ls"));
    EXPECT_EQ(c["methods"]["lad"]["vs_ls"]["torque_err_mean"]["n"], 2);
    EXPECT_EQ(c["methods"]["lad"]["vs_ls"]["median_abs_rel_err"]["n"], 2);
  }
  // Noise-free records: LS recovers every base parameter with a non-zero truth within 2 % (the
  // error left is the processing's and the encoder's, which the noisy cells only add to).
  EXPECT_LT(summary["conditions"][0]["methods"]["ls"]["metrics"]["max_abs_rel_err"]["mean"].get<double>(), 0.02);
  const std::string md = slurp(d + "/summary.md");
  EXPECT_NE(md.find("# Sweep summary: --model leg3"), std::string::npos);
  EXPECT_NE(md.find("| knee.Ia |"), std::string::npos);
}

// The rig's axes on any leg: vibration and encoder backlash are grid factors of a chain sweep. A
// cell per level, its condition in every table; a vibrating cell's runs fit the base-motion terms
// (its records carry the IMU) in the still base's parameters, as identify --model does.
TEST(ChainSweep, VibrationAndBacklashAreAxesOfAChainSweep) {
  const std::string d = freshDir("chain_axes");
  const std::string cfg = writeToml("axes", "[sweep]\nmodel = \"leg3\"\nseeds = 1\nmethods = [\"ls\"]\n"
                                            "[grid]\ntorque_noise_Nm = [0.0]\nvibration_level = [0.0, 1.0]\nencoder_backlash_deg = [0.0, 0.1]\n"
                                            "trajectories = [\"default\"]\n[simulation]\nduration_s = 4.0\n");
  ASSERT_EQ(runExoid({"sweep", "--config", cfg, "--out", d}), 0);
  const nlohmann::json summary = exoid::test::readJson(d + "/summary.json");
  ASSERT_EQ(summary["conditions"].size(), 4u);
  const LoadedChain leg3 = loadChain("leg3");
  std::map<std::pair<double, double>, int> seen;
  for (const nlohmann::json& c : summary["conditions"]) {
    const double level = c["condition"]["vibration_level"], play = c["condition"]["encoder_backlash_deg"];
    ++seen[{level, play}];
    EXPECT_EQ(c["methods"]["ls"]["n"], 1) << c.dump();
    const auto names = c["base_parameters"]["names"].get<std::vector<std::string>>();
    EXPECT_EQ(names, leg3.base.names) << level;
  }
  EXPECT_EQ(seen.size(), 4u);
  const std::string csv = slurp(d + "/summary.csv");
  EXPECT_EQ(csv.rfind("cell,torque_noise_Nm,angle_noise_deg,quantisation_deg,vibration_level,cylinder_mass_scale,encoder_backlash_deg,", 0), 0u);
  const std::string md = slurp(d + "/summary.md");
  EXPECT_NE(md.find("## default motion, vibration level 1, angle noise"), std::string::npos) << md;
  EXPECT_NE(md.find("encoder backlash 0.1 deg"), std::string::npos) << md;
}

TEST(ChainSweep, ThreadsShardsMergeAndResumeGiveTheSameBytes) {
  const std::string& ref = referenceChainSweep();
  const std::string cfg = tinyChainConfig();
  const std::string one = freshDir("chain_one_thread");
  ASSERT_EQ(runExoid({"sweep", "--config", cfg, "--out", one, "--threads", "1"}), 0);
  expectSameSweep(ref, one);
  const std::string s0 = freshDir("chain_shard0"), s1 = freshDir("chain_shard1"), merged = freshDir("chain_merged");
  ASSERT_EQ(runExoid({"sweep", "--config", cfg, "--out", s0, "--shard", "0/2"}), 0);
  ASSERT_EQ(runExoid({"sweep", "--config", cfg, "--out", s1, "--shard", "1/2"}), 0);
  ASSERT_EQ(runExoid({"merge", "--out", merged, s0, s1}), 0);
  expectSameSweep(ref, merged);
  // A rerun into a finished folder does nothing and changes nothing.
  const std::string before = slurp(one + "/summary.md");
  ASSERT_EQ(runExoid({"sweep", "--config", cfg, "--out", one}), 0);
  EXPECT_EQ(slurp(one + "/summary.md"), before);
  // The folder's config.json names the model, not its path (resume from elsewhere, shards elsewhere).
  EXPECT_EQ(exoid::test::readJson(one + "/config.json")["sweep"]["model"], "leg3");
  // A sweep started in a folder keeps its design: without [simulation] excitation, the one in
  // config.json is taken (no new design.json), so a resume never designs again.
  SweepConfig undesigned = loadSweepConfig(cfg);
  undesigned.chain_design.reset();
  std::ostringstream log;
  const SweepConfig kept = withChainDesign(undesigned, one, log);
  ASSERT_TRUE(kept.chain_design.has_value());
  EXPECT_EQ(kept.toJson().dump(), exoid::test::readJson(one + "/config.json").dump());
  EXPECT_FALSE(std::filesystem::exists(one + "/design.json"));
  EXPECT_NE(log.str().find("config.json"), std::string::npos) << log.str();
  // Another model's sweep is refused in this folder (its config.json differs).
  EXPECT_NE(runExoid({"sweep", "--out", one, "--seeds", "2", "--duration", "2", "--noise-tau", "0"}), 0);
}

}  // namespace exoid::experiments::sweep_chain_tests
