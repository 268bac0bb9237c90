// `exoid excite` end to end: the design file, and the simulated record of it inside the limits
// (checked on what the simulator recorded, not only on the design).
#include "cli_test_support.hpp"
#include "exoid/experiments/protocol/excitation_io.hpp"
#include "exoid/ident/io/dataset.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace exoid::experiments {
namespace {

using exoid::test::runExoid;

using exoid::test::readJson;

TEST(ExciteCli, DesignFileSimulatesInsideItsLimits) {
  const std::string dir = ::testing::TempDir();
  const std::string design = dir + "/excite_design.json", csv = dir + "/excite_record.csv";
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"excite", "--out", design, "--restarts", "2", "--max-evaluations", "600", "--seed", "3"}), 0);
  testing::internal::GetCapturedStdout();
  const nlohmann::json j = readJson(design);
  EXPECT_EQ(j["seed"], 3);
  EXPECT_EQ(j["options"]["criterion"], "crb");
  EXPECT_TRUE(std::filesystem::exists(dir + "/excite_design.png"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/excite_design_series.csv"));
  // No design beats the floor.
  for (const auto& [name, floor] : j["comparison"]["crb_floor_std"].items()) {
    EXPECT_GE(j["comparison"]["crb_std"][name].get<double>(), floor.get<double>()) << name;
  }
  EXPECT_LT(j["score"]["condition_number"].get<double>(), j["comparison"]["paper_condition_number"].get<double>());
  // Two periods (10 s) simulated without noise, on the rig the nominal model describes exactly
  // (no cylinder mass, welded mount): the recorded true angles, speeds, accelerations and motor
  // torques inside the limits up to what the tracking error (0.01 deg RMS on this rig) moves
  // them: 1e-3 rad, 1e-2 rad/s, and 1 % of the acceleration and torque limits allowed (measured
  // 0.005 rad/s^2 and 0.002 N m between the design's and the record's peaks).
  ASSERT_EQ(runExoid({"simulate", "--excitation", design, "--duration", "10", "--noise-q-deg", "0", "--quantisation-deg", "0",
                      "--noise-tau", "0", "--cylinder-mass-scale", "0", "--vibration", "0", "--out", csv}),
            0);
  const ident::Dataset d = ident::readDatasetCsv(csv);
  const nlohmann::json& lim = j["limits"];
  const char* q_cols[2] = {"q_hip_true", "q_knee_true"};
  const char* qd_cols[2] = {"qd_hip_true", "qd_knee_true"};
  const char* qdd_cols[2] = {"qdd_hip_true", "qdd_knee_true"};
  const char* tau_cols[2] = {"tau_hip_true", "tau_knee_true"};
  for (int k = 0; k < 2; ++k) {
    const Eigen::VectorXd q = d.extraColumn(q_cols[k]), qd = d.extraColumn(qd_cols[k]);
    EXPECT_GE(q.minCoeff(), lim["q_min_rad"][k].get<double>() - 1e-3) << q_cols[k];
    EXPECT_LE(q.maxCoeff(), lim["q_max_rad"][k].get<double>() + 1e-3) << q_cols[k];
    EXPECT_LE(qd.cwiseAbs().maxCoeff(), lim["qd_max_radps"][k].get<double>() + 1e-2) << qd_cols[k];
    const Eigen::VectorXd qdd = d.extraColumn(qdd_cols[k]), tau = d.extraColumn(tau_cols[k]);
    EXPECT_LE(qdd.cwiseAbs().maxCoeff(), 1.01 * lim["qdd_max_radps2"][k].get<double>()) << qdd_cols[k];
    EXPECT_LE(tau.cwiseAbs().maxCoeff(), 1.01 * lim["tau_max_Nm"][k].get<double>()) << tau_cols[k];
    // The record reaches what the design reached (the limits are not met by a lazy simulation).
    EXPECT_NEAR(tau.cwiseAbs().maxCoeff(), j["score"]["reached"]["tau_max_Nm"][k].get<double>(),
                0.01 * lim["tau_max_Nm"][k].get<double>()) << tau_cols[k];
  }
  // The design round-trips through the file.
  const core::FourierSeries t = readExcitationFile(design, kLegJoints).series;
  EXPECT_EQ(t.a_rad(0, 1), j["trajectory"]["joints"][1]["cos_rad"][0].get<double>());
}

// Same seed, same bytes: the design, its series and its figure (no times or dates in them).
TEST(ExciteCli, SameSeedSameBytes) {
  const std::string dir = ::testing::TempDir();
  const std::vector<std::string> args = {"excite", "--knee-only", "--restarts", "2", "--max-evaluations", "400", "--seed", "5", "--out"};
  testing::internal::CaptureStdout();
  auto a = args, b = args;
  a.push_back(dir + "/same_a.json");
  b.push_back(dir + "/same_b.json");
  ASSERT_EQ(runExoid(a), 0);
  ASSERT_EQ(runExoid(b), 0);
  testing::internal::GetCapturedStdout();
  const auto slurp = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  for (const char* suffix : {".json", "_series.csv", ".png"}) {
    const std::string x = slurp(dir + "/same_a" + suffix), y = slurp(dir + "/same_b" + suffix);
    EXPECT_FALSE(x.empty()) << suffix;
    EXPECT_EQ(x, y) << suffix;
  }
}

// `exoid simulate --excitation FILE` (FILE holding `design`, after `model_args`): a non-zero exit,
// and what it printed on stderr.
std::string refusedDesign(const std::string& name, const std::string& design, std::vector<std::string> model_args = {}) {
  const std::string file = ::testing::TempDir() + "/" + name;
  std::ofstream(file) << design;
  std::vector<std::string> args = {"simulate"};
  args.insert(args.end(), model_args.begin(), model_args.end());
  for (const std::string& s : {std::string("--excitation"), file, std::string("--out"), ::testing::TempDir() + "/never.csv"}) args.push_back(s);
  testing::internal::CaptureStderr();
  EXPECT_NE(runExoid(args), 0) << name;
  return testing::internal::GetCapturedStderr();
}

TEST(ExciteCli, BadExcitationFileIsNamed) {
  const std::string err = refusedDesign(
      "bad_excitation.json", R"({"trajectory": {"f0_hz": 0.1, "locked_joints": 0, "joints": [{"name": "hip", "cos_rad": [0.1], "sin_rad": [0]}]}})");
  EXPECT_NE(err.find("bad_excitation.json"), std::string::npos) << err;
  EXPECT_NE(err.find("offset_rad"), std::string::npos) << err;
  // Another robot's design (leg3's three joints) on the APAL leg: refused, naming both joint lists.
  const std::string err2 = refusedDesign("leg3_excitation.json", R"({"trajectory": {"f0_hz": 0.1, "locked_joints": 0, "joints": [)"
                                                                 R"({"name": "hip", "offset_rad": 0, "cos_rad": [0.1], "sin_rad": [0]},)"
                                                                 R"({"name": "knee", "offset_rad": 0.5, "cos_rad": [0.1], "sin_rad": [0]},)"
                                                                 R"({"name": "ankle", "offset_rad": 0, "cos_rad": [0.1], "sin_rad": [0]}]}})");
  EXPECT_NE(err2.find("--excitation"), std::string::npos) << err2;
  EXPECT_NE(err2.find("hip, knee, ankle"), std::string::npos) << err2;
  // And the other way: the APAL leg's two joints on leg3, named the same way.
  const std::string err3 = refusedDesign("apal_excitation.json", R"({"trajectory": {"f0_hz": 0.1, "locked_joints": 0, "joints": [)"
                                                                 R"({"name": "hip", "offset_rad": 0, "cos_rad": [0.1], "sin_rad": [0]},)"
                                                                 R"({"name": "knee", "offset_rad": 0.5, "cos_rad": [0.1], "sin_rad": [0]}]}})",
                                         {"--model", "leg3"});
  EXPECT_NE(err3.find("the design moves hip, knee; this robot's joints are hip, knee, ankle"), std::string::npos) << err3;
  // A design in the form exoid wrote before (a_rad, b_rad) is named as such.
  const std::string err4 = refusedDesign("older_excitation.json", R"({"trajectory": {"f0_hz": 0.1, "hip_locked": false, "offset_rad": {"hip": 0, "knee": 0.5},)"
                                                                  R"("a_rad": {"hip": [0.1], "knee": [0.1]}, "b_rad": {"hip": [0], "knee": [0]}}})");
  EXPECT_NE(err4.find("older exoid's form"), std::string::npos) << err4;
}

}  // namespace
}  // namespace exoid::experiments
