// The commands on the built-in hip-knee-ankle leg, through the CLI as a user runs them: excite
// designs for it, simulate runs the design, identify recovers the base parameters of the exact
// record (every method, IDIM-IV with the controller the record carries); what the chain path does
// not take is refused by name.
#include "cli_test_support.hpp"
#include "exoid/core/format.hpp"
#include "exoid/experiments/commands/robot_commands.hpp"
#include "exoid/experiments/protocol/robot_loader.hpp"
#include "exoid/experiments/report/table.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <cmath>
#include <fstream>
#include <sstream>

namespace exoid::experiments {
namespace {

using exoid::test::runExoid;

using exoid::test::readJson;
using exoid::test::slurp;

std::string stderrOf(const std::vector<std::string>& args, int expected_code) {
  testing::internal::CaptureStderr();
  testing::internal::CaptureStdout();
  EXPECT_EQ(runExoid(args), expected_code);
  testing::internal::GetCapturedStdout();
  return testing::internal::GetCapturedStderr();
}

TEST(ChainCli, ExciteSimulateIdentifyTheHipKneeAnkleLeg) {
  const std::string dir = ::testing::TempDir();
  const std::string design = dir + "/leg3_design.json", csv = dir + "/leg3_exact.csv", side = dir + "/leg3_exact.json",
                    out = dir + "/leg3_identified.json";
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"excite", "--model", "leg3", "--restarts", "2", "--out", design}), 0);
  const nlohmann::json d = readJson(design);
  EXPECT_LE(d["score"]["condition_number"].get<double>(), 10.0);
  EXPECT_EQ(d["score"]["worst_violation"].get<double>(), 0.0);
  ASSERT_EQ(d["trajectory"]["joints"].size(), 3u);
  EXPECT_EQ(d["limits"]["tau_max_Nm"].size(), 3u);
  ASSERT_EQ(runExoid({"simulate", "--model", "leg3", "--excitation", design, "--duration", "10", "--coulomb-v0", "0",
                      "--record-derivatives", "--out", csv}),
            0);
  ASSERT_EQ(runExoid({"identify", "--model", "leg3", "--data", csv, "--truth", side, "--json", out}), 0);
  testing::internal::GetCapturedStdout();
  const nlohmann::json r = readJson(out);
  const auto& b = r["base_parameters"];
  ASSERT_EQ(b["names"].size(), 17u);
  for (std::size_t i = 0; i < 17; ++i) {
    const double truth = b["truth"][i].get<double>(), ls = b["ls"][i].get<double>();
    EXPECT_NEAR(ls, truth, 1e-6 * std::max(1.0, std::abs(truth))) << b["names"][i].get<std::string>();
  }
  EXPECT_EQ(r["consistent"]["status"], "least_squares_consistent");
  EXPECT_EQ(r["status"], "usable");
  // The paper's other methods over the same base-parameter rows: on exact data LAD is exact too,
  // RLS (P0 = 1e6 I) within its prior's pull, 1e-6 of the largest parameter.
  const std::string out3 = dir + "/leg3_methods.json";
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"identify", "--model", "leg3", "--data", csv, "--truth", side, "--method", "ls,rls,lad,iv-band,idim-iv", "--json", out3}), 0);
  testing::internal::GetCapturedStdout();
  const nlohmann::json mth = readJson(out3)["methods"];
  // IDIM-IV's instruments simulate ident's own model of the closed loop, not MuJoCo's: on exact rows
  // the estimate is exact whatever the instruments.
  for (const char* m : {"rls", "lad", "iv-band", "idim-iv"}) {
    ASSERT_TRUE(mth.contains(m)) << m;
    for (std::size_t i = 0; i < 17; ++i) {
      EXPECT_NEAR(mth[m]["beta"][i].get<double>(), b["truth"][i].get<double>(), 1e-6 * 5.5) << m << " " << b["names"][i].get<std::string>();
    }
  }
  // The URDF of the same leg has no armature: --armature all adds it; the estimate predicts the
  // (exact) record to rounding, and the figure is drawn.
  const std::string urdf = std::string(EXOID_SOURCE_DIR) + "/models/leg3.urdf", png = dir + "/leg3_fit.png", out2 = dir + "/leg3_urdf.json";
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"identify", "--model", urdf, "--armature", "all", "--data", csv, "--validate", csv, "--truth", side, "--plot", png,
                      "--json", out2}),
            0);
  testing::internal::GetCapturedStdout();
  const nlohmann::json u = readJson(out2);
  EXPECT_EQ(u["base_parameters"]["names"], b["names"]);
  for (const auto& joint : u["validation"][0]["joints"]) {
    EXPECT_LE(joint["rms_error_Nm"].get<double>(), 1e-8 * joint["rms_measured_Nm"].get<double>()) << joint["name"];
  }
  EXPECT_TRUE(std::filesystem::exists(png));
  EXPECT_TRUE(std::filesystem::exists(dir + "/leg3_fit_series.csv"));
  EXPECT_NE(stderrOf({"identify", "--model", urdf, "--armature", "toe", "--data", csv}, 1).find("'toe' is not a joint of leg3"), std::string::npos);
  // Without its model the record is refused, naming the joint the APAL leg does not have.
  const std::string err = stderrOf({"identify", "--data", csv}, 1);
  EXPECT_NE(err.find("a joint 'ankle'"), std::string::npos) << err;
}

// truth of a chain: its standard and base parameters, never the 2-link leg's X of two of its joints.
TEST(ChainCli, TruthOfAChainIsItsOwnParameters) {
  const std::string dir = ::testing::TempDir();
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"truth", "--model", "leg3", "--json", dir + "/leg3_truth.json"}), 0);
  ASSERT_EQ(runExoid({"truth", "--urdf", std::string(EXOID_SOURCE_DIR) + "/models/leg3.urdf", "--json", dir + "/leg3_urdf_truth.json"}), 0);
  testing::internal::GetCapturedStdout();
  const nlohmann::json m = readJson(dir + "/leg3_truth.json"), u = readJson(dir + "/leg3_urdf_truth.json");
  EXPECT_EQ(m["truth"]["base_parameters"].size(), 17u);
  EXPECT_EQ(u["truth"]["base_parameters"].size(), 15u);  // no armature in a URDF
  EXPECT_EQ(m["truth"]["standard_parameters"]["foot.mx"], u["truth"]["standard_parameters"]["foot.mx"]);
  EXPECT_FALSE(m.contains("parameters"));
}

// The chain's twin of IdentifyCli.AHipLockedRecordExitsThreeNamingTheHipParametersAndServesAsTheKneeRecord:
// a leg3 record whose hip is locked does not determine the base parameters of the thigh and the
// hip joint, whatever the condition number reads: exit 3 naming them; the segmental strategy
// takes the same record as its knee stage.
TEST(ChainCli, AHipLockedRecordExitsThreeNamingTheHipsBaseParameters) {
  const std::string dir = ::testing::TempDir() + "/hip_locked_chain";
  std::filesystem::create_directories(dir);
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"simulate", "--model", "leg3", "--duration", "6", "--seed", "4", "--lock", "hip", "--out", dir + "/locked.csv"}), 0);
  EXPECT_EQ(runExoid({"identify", "--model", "leg3", "--data", dir + "/locked.csv", "--json", dir + "/locked.json"}), 3);
  testing::internal::GetCapturedStdout();
  const nlohmann::json j = readJson(dir + "/locked.json");
  const nlohmann::json& names = j["determination"]["not_determined"];
  ASSERT_GE(names.size(), 3u) << j["determination"];
  for (const auto& n : names) {
    const std::string s = n.get<std::string>();
    EXPECT_TRUE(s.rfind("thigh.", 0) == 0 || s.rfind("hip.", 0) == 0) << s;
  }
  EXPECT_FALSE(j["determination"]["records"][0]["joints_rad"][0]["moved"].get<bool>());
  EXPECT_NE(j["problems"][0].get<std::string>().find("hip held in every record"), std::string::npos) << j["problems"];
  EXPECT_EQ(j["status"], "not_usable");  // as the APAL leg's identify says it
  // The segmental strategy: the same record as the knee stage, then one where every joint moves,
  // determines everything; with the hip held in the last stage too, the same hip parameters are
  // named (the stages' determination is judged over all their records together).
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"simulate", "--model", "leg3", "--duration", "6", "--seed", "5", "--out", dir + "/all.csv"}), 0);
  EXPECT_EQ(runExoid({"identify", "--model", "leg3", "--stage", "knee=" + dir + "/locked.csv", "--data", dir + "/all.csv", "--json",
                      dir + "/staged.json"}),
            0);
  EXPECT_TRUE(readJson(dir + "/staged.json")["determination"]["not_determined"].empty());
  EXPECT_EQ(runExoid({"identify", "--model", "leg3", "--stage", "knee=" + dir + "/locked.csv", "--data", dir + "/locked.csv", "--json",
                      dir + "/held.json"}),
            3);
  testing::internal::GetCapturedStdout();
  const nlohmann::json held = readJson(dir + "/held.json");
  EXPECT_EQ(held["determination"]["not_determined"], names);
  ASSERT_EQ(held["determination"]["records"].size(), 2u);  // the knee stage's record, then --data's
  EXPECT_EQ(held["determination"]["records"][0]["file"], dir + "/locked.csv");
  EXPECT_NE(held["problems"][0].get<std::string>().find("hip held in every record"), std::string::npos) << held["problems"];
  // Each stage is judged on its own motion: a knee stage whose knee was locked too leaves the
  // shank's and the knee's own parameters open, though the last stage's hip equation sees some.
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"simulate", "--model", "leg3", "--duration", "6", "--seed", "4", "--lock", "hip,knee", "--out", dir + "/ankle_only.csv"}), 0);
  EXPECT_EQ(runExoid({"identify", "--model", "leg3", "--stage", "knee=" + dir + "/ankle_only.csv", "--data", dir + "/all.csv", "--json",
                      dir + "/knee_open.json"}),
            3);
  testing::internal::GetCapturedStdout();
  const nlohmann::json open = readJson(dir + "/knee_open.json")["determination"]["not_determined"];
  ASSERT_FALSE(open.empty());
  for (const auto& n : open) {
    const std::string s = n.get<std::string>();
    EXPECT_TRUE(s.rfind("shank.", 0) == 0 || s.rfind("knee.", 0) == 0) << s;
  }
}

// Every method's estimate is judged for physical consistency, as LS's is (and as the APAL leg's
// identify judges each method): the file's own parameters are consistent, at no distance; a
// negative viscous friction is not, and lies |value| / its standard error away (the friction's
// bound is the nearest consistent point, the other parameters free): the method is named.
TEST(ChainCli, EveryMethodsEstimateIsJudgedForPhysicalConsistency) {
  const LoadedChain leg = loadChain("leg3");
  const Eigen::VectorXd cad = leg.base.combination * leg.phi;
  const Eigen::VectorXd sd = 0.01 * cad.cwiseAbs().array() + 1e-3;
  const Eigen::MatrixXd covariance = sd.array().square().matrix().asDiagonal();
  const std::optional<NearestConsistent> own = nearestConsistent(leg, cad, covariance, "the file's", {});
  ASSERT_TRUE(own);
  EXPECT_EQ(own->fit.status, ident::ConsistentFitStatus::kLeastSquaresConsistent);
  EXPECT_EQ(own->verdict.distance, 0.0);
  const auto fv = std::find(leg.base.names.begin(), leg.base.names.end(), "hip.fv");
  ASSERT_NE(fv, leg.base.names.end());
  const auto i = static_cast<Eigen::Index>(fv - leg.base.names.begin());
  Eigen::VectorXd negative = cad;
  negative[i] = -10.0 * sd[i];
  ChainFit fit;
  fit.others = {{"lad", cad}, {"pso", negative}};
  ChainIdentifyArgs args;
  testing::internal::CaptureStdout();
  judgeOthersConsistency(args, leg, covariance, fit);
  testing::internal::GetCapturedStdout();
  EXPECT_TRUE(fit.json["methods"]["lad"]["consistent"]["consistent"].get<bool>());
  EXPECT_FALSE(fit.json["methods"]["pso"]["consistent"]["consistent"].get<bool>());
  EXPECT_NEAR(fit.json["methods"]["pso"]["consistent"]["ls_standard_errors_from_estimate"].get<double>(), 10.0, 1e-3);
  ASSERT_EQ(fit.problems.size(), 1u);
  EXPECT_EQ(fit.problems[0].rfind("pso: no physically consistent body explains its estimate", 0), 0u) << fit.problems[0];
}

TEST(ChainCli, SegmentalStrategyDownTheLegRecoversExactRecordsStageByStage) {
  // The paper's strategy on the 3-DOF leg: an ankle record with hip and knee locked, a knee record
  // with the hip locked, then every joint. Exact records (sgn Coulomb, recorded derivatives): every
  // base parameter within 1e-6; stage 1 fits the foot's and ankle's, and the lock joins foot.Iyy
  // with ankle.Ia, which the knee stage separates.
  const std::string dir = ::testing::TempDir() + "/segmental";
  std::filesystem::create_directories(dir);
  testing::internal::CaptureStdout();
  const std::vector<std::string> exact = {"--duration", "10", "--coulomb-v0", "0", "--record-derivatives"};
  const auto simulate = [&](const std::string& out, const std::string& lock, const std::string& seed) {
    std::vector<std::string> args = {"simulate", "--model", "leg3", "--out", dir + "/" + out, "--seed", seed};
    args.insert(args.end(), exact.begin(), exact.end());
    if (!lock.empty()) args.insert(args.end(), {"--lock", lock});
    return runExoid(args);
  };
  ASSERT_EQ(simulate("ankle.csv", "hip,knee", "1"), 0);
  ASSERT_EQ(simulate("knee.csv", "hip", "2"), 0);
  ASSERT_EQ(simulate("all.csv", "", "3"), 0);
  const std::string out = dir + "/segmental.json";
  ASSERT_EQ(runExoid({"identify", "--model", "leg3", "--stage", "ankle=" + dir + "/ankle.csv", "--stage", "knee=" + dir + "/knee.csv",
                      "--data", dir + "/all.csv", "--truth", dir + "/all.json", "--method", "ls,lad", "--validate", dir + "/all.csv", "--json", out}),
            0);
  const std::string printed = testing::internal::GetCapturedStdout();
  // Each stage says how well its records excite what it identifies, as one fit does.
  std::size_t excitations = 0;
  for (std::size_t at = printed.find("excitation of the stage's records: condition number"); at != std::string::npos;
       at = printed.find("excitation of the stage's records: condition number", at + 1)) {
    ++excitations;
  }
  EXPECT_EQ(excitations, 3u) << printed;
  const nlohmann::json a = readJson(dir + "/ankle.json");
  EXPECT_EQ(a["config"]["locked"], nlohmann::json({"hip", "knee"}));
  const nlohmann::json r = readJson(out);
  ASSERT_EQ(r["stages"].size(), 3u);
  EXPECT_EQ(r["stages"][0]["first_joint"], "ankle");
  EXPECT_EQ(r["stages"][0]["locked"], "hip, knee");
  EXPECT_EQ(r["stages"][0]["identifies"].size(), 5u);
  bool joined = false;
  for (const auto& n : r["stages"][0]["identifies"]) joined = joined || (n.get<std::string>().find("ankle.Ia") != std::string::npos && n.get<std::string>().find("foot.Iyy") != std::string::npos);
  EXPECT_TRUE(joined) << r["stages"][0]["identifies"];
  const nlohmann::json& b = r["base_parameters"];
  ASSERT_EQ(b["names"].size(), 17u);
  // LS's standard errors stage by stage (ident::segmentalReportedErrors, against Monte Carlo in
  // SegmentalErrors.*): one per base parameter, at rounding level on exact records.
  ASSERT_EQ(b["std_error"].size(), 17u);
  for (std::size_t i = 0; i < 17; ++i) EXPECT_LT(b["std_error"][i].get<double>(), 1e-6) << b["names"][i].get<std::string>();
  // The validation records and the model file's own parameters, as one fit's: on an exact record
  // the estimate predicts the torque to rounding (relative 1e-6, as the parameters).
  ASSERT_EQ(r["validation"].size(), 1u);
  for (const auto& joint : r["validation"][0]["joints"]) {
    EXPECT_LT(joint["rms_error_Nm"].get<double>(), 1e-6 * joint["rms_measured_Nm"].get<double>()) << joint.dump();
  }
  EXPECT_EQ(r["validation"][0]["methods_rms_error_Nm"]["lad"].size(), 3u);
  EXPECT_EQ(b["cad"].size(), 17u);
  // Physical consistency judged in those errors, as one fit's: the truth is a real leg, so LS is.
  EXPECT_EQ(r["consistent"]["status"], "least_squares_consistent");
  EXPECT_EQ(r["consistent"]["standard_errors_from_ls"].get<double>(), 0.0);
  EXPECT_EQ(b["consistent"].size(), 17u);
  for (const char* m : {"ls", "lad"}) {
    for (std::size_t i = 0; i < 17; ++i) {
      const double truth = b["truth"][i].get<double>();
      const nlohmann::json& x = std::string(m) == "ls" ? b["ls"] : r["methods"][m]["beta"];
      EXPECT_NEAR(x[i].get<double>(), truth, 1e-6 * std::max(1.0, std::abs(truth))) << m << " " << b["names"][i].get<std::string>();
    }
  }
  // The APAL leg's spelling of a knee stage is every leg's: the same bytes.
  const std::string spelled = dir + "/segmental_knee_data.json", generic = dir + "/segmental_knee_stage.json";
  testing::internal::CaptureStdout();
  const int spelled_code = runExoid({"identify", "--model", "leg3", "--knee-data", dir + "/knee.csv", "--both-data", dir + "/all.csv",
                                     "--knee-armature", "--json", spelled});
  const int generic_code = runExoid({"identify", "--model", "leg3", "--stage", "knee=" + dir + "/knee.csv", "--data", dir + "/all.csv",
                                     "--armature", "knee", "--json", generic});
  testing::internal::GetCapturedStdout();
  EXPECT_TRUE(generic_code == 0 || generic_code == 3) << generic_code;
  EXPECT_EQ(spelled_code, generic_code);
  EXPECT_EQ(slurp(spelled), slurp(generic));
  // One report for both strategies: the one fit of the same --data writes the same common part
  // (inputs with each record's sampling, the options as run, the seed, the CAD comparison, every
  // other method's error against the truth) as the stages do.
  const std::string once = dir + "/once.json";
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"identify", "--model", "leg3", "--data", dir + "/all.csv", "--truth", dir + "/all.json", "--method", "ls,lad", "--json", once}), 0);
  testing::internal::GetCapturedStdout();
  const nlohmann::json o = readJson(once);
  for (const nlohmann::json* j : {&r, &o}) {
    EXPECT_EQ((*j)["command"], "identify");
    EXPECT_EQ((*j)["inputs"]["data"], nlohmann::json({dir + "/all.csv"}));
    EXPECT_EQ((*j)["inputs"]["sampling"][dir + "/all.csv"]["rows_used"], 10000);  // 10 s at 1 kHz
    EXPECT_EQ((*j)["signal_options"], o["signal_options"]);
    // The PSO box as the methods ran: 10 x the largest |LS estimate| (no --wide-box given).
    double biggest = 0.0;
    for (const auto& x : (*j)["base_parameters"]["ls"]) biggest = std::max(biggest, std::abs(x.get<double>()));
    EXPECT_NEAR((*j)["method_options"]["pso"]["wide_box_half_width"].get<double>(), 10.0 * biggest, 1e-12 * biggest);
    EXPECT_EQ((*j)["seed"], o["seed"]);
    EXPECT_EQ((*j)["base_parameters"]["ls_minus_cad_std_errors"].size(), 17u);
    EXPECT_EQ((*j)["methods"]["lad"]["error_rel"].size(), 17u);
    for (std::size_t i = 0; i < 17; ++i) {  // relative where the truth is not 0, else null
      EXPECT_EQ((*j)["methods"]["lad"]["error_rel"][i].is_null(), (*j)["base_parameters"]["truth"][i].get<double>() == 0.0) << i;
    }
    EXPECT_TRUE((*j)["methods"]["lad"]["consistent"]["consistent"].get<bool>()) << (*j)["methods"]["lad"];  // exact: the truth's
    EXPECT_EQ((*j)["model"]["joints"], nlohmann::json({"hip", "knee", "ankle"}));
  }
  EXPECT_EQ(r["inputs"]["stages"].size(), 2u);
  EXPECT_EQ(r["inputs"]["sampling"].size(), 3u);
  EXPECT_EQ(o["strategy"], "all_parameters_one_record");
  // The stages' band sensitivity, as one fit's: every chosen cutoff a quarter wider, LS down the
  // stages again. Exact records stay exact in any band (W and y filtered alike), so the refit
  // ls + shift x std err is the truth to 1e-6 too.
  const nlohmann::json& sensitivity = r["band_sensitivity"];
  EXPECT_EQ(sensitivity["cutoff_factor"].get<double>(), 1.25);
  ASSERT_EQ(sensitivity["shift_standard_errors"].size(), 17u);
  for (std::size_t i = 0; i < 17; ++i) {
    const std::string name = b["names"][i].get<std::string>();
    const double wider = b["ls"][i].get<double>() + sensitivity["shift_standard_errors"][name].get<double>() * b["std_error"][i].get<double>();
    const double truth = b["truth"][i].get<double>();
    EXPECT_NEAR(wider, truth, 1e-6 * std::max(1.0, std::abs(truth))) << name;
  }
  // What cannot work is refused by name.
  EXPECT_NE(stderrOf({"identify", "--model", "leg3", "--stage", "toe=" + dir + "/ankle.csv", "--data", dir + "/all.csv"}, 1).find("'toe' is not a joint"),
            std::string::npos);
  EXPECT_NE(stderrOf({"identify", "--model", "leg3", "--stage", "ankle=" + dir + "/ankle.csv"}, 1).find("needs --data"), std::string::npos);
  EXPECT_NE(stderrOf({"simulate", "--model", "leg3", "--lock", "toe", "--out", dir + "/x.csv"}, 1).find("cannot lock joint 'toe'"), std::string::npos);
}

// Noisy stage records (5 s, 2 N m torque noise): LS lies outside the physically consistent set, and
// the distance to it is judged in LS's reported errors, as one fit's is: within --significance it is
// the bound, not drawn; beyond it (--significance d / 2), estimates drawn about a consistent body
// decide (ident::judgeConsistency), and here as many lie as far (p above the level): exit 0, the
// same distance. The verdict's exit 3 through nearestConsistent, which the stages use, is
// ChainCli.EveryMethodsEstimateIsJudgedForPhysicalConsistency's.
TEST(ChainCli, SegmentalStrategyJudgesConsistencyInItsReportedErrors) {
  const std::string dir = ::testing::TempDir() + "/segmental_noisy";
  std::filesystem::create_directories(dir);
  testing::internal::CaptureStdout();
  const auto simulate = [&](const std::string& out, const std::string& seed, const std::vector<std::string>& lock) {
    std::vector<std::string> args = {"simulate", "--model", "leg3", "--duration", "5", "--noise-tau", "2", "--seed", seed, "--out", dir + "/" + out};
    args.insert(args.end(), lock.begin(), lock.end());
    return runExoid(args);
  };
  ASSERT_EQ(simulate("ankle.csv", "11", {"--lock", "hip,knee"}), 0);
  ASSERT_EQ(simulate("knee.csv", "12", {"--lock", "hip"}), 0);
  ASSERT_EQ(simulate("all.csv", "13", {}), 0);
  const std::string out = dir + "/segmental.json";
  const std::vector<std::string> identify = {"identify", "--model", "leg3", "--stage", "ankle=" + dir + "/ankle.csv", "--stage",
                                             "knee=" + dir + "/knee.csv", "--data", dir + "/all.csv", "--json", out};
  ASSERT_EQ(runExoid(identify), 0);
  const nlohmann::json r = readJson(out);
  EXPECT_EQ(r["consistent"]["status"], "constrained");
  const double d = r["consistent"]["standard_errors_from_ls"].get<double>();
  EXPECT_GT(d, 0.0);
  EXPECT_LT(d, 2.0);
  EXPECT_EQ(r["consistent"]["verdict"]["draws"].get<int>(), 0);
  std::vector<std::string> half = identify;
  half.insert(half.end(), {"--significance", fmt(0.5 * d, 4)});
  EXPECT_EQ(runExoid(half), 0);
  testing::internal::GetCapturedStdout();
  const nlohmann::json drawn = readJson(out)["consistent"]["verdict"];
  EXPECT_EQ(drawn["draws"].get<int>(), 199);
  EXPECT_EQ(drawn["standard_errors"].get<double>(), d);
  EXPECT_GT(drawn["p_value"].get<double>(), drawn["level"].get<double>());
}

TEST(ChainCli, ReproduceOnTheHipKneeAnkleLegRunsTheProtocolAndReportsEveryBaseParameter) {
  // reproduce --model leg3: design, records (fit, validation, one per segmental stage), one fit and
  // the segmental strategy by LS and LAD, report.md with every base parameter. Noise-free records:
  // LS within 2 % of the truth in median (what is left is the simulator's smooth Coulomb and the
  // differentiated angles).
  const std::string dir = ::testing::TempDir() + "/reproduce_leg3";
  testing::internal::CaptureStdout();
  // Two restarts of the design (its quality is ChainCli.ExciteSimulate...'s subject, not this test's).
  const int code = runExoid({"reproduce", "--model", "leg3", "--out", dir, "--methods", "ls,lad", "--no-plots", "--noise-q-deg", "0",
                             "--quantisation-deg", "0", "--noise-tau", "0", "--seed", "4", "--design-restarts", "2"});
  testing::internal::GetCapturedStdout();
  ASSERT_EQ(code, 0);
  for (const char* f : {"design.json", "fit.csv", "fit.json", "check.csv", "stage_ankle.csv", "stage_knee.csv", "identify.json",
                        "segmental.json", "report.md"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + f)) << f;
  }
  EXPECT_EQ(readJson(dir + "/stage_ankle.json")["config"]["locked"], nlohmann::json({"hip", "knee"}));
  EXPECT_EQ(readJson(dir + "/fit.json")["config"]["seed"].get<std::uint64_t>() != readJson(dir + "/check.json")["config"]["seed"].get<std::uint64_t>(), true);
  const nlohmann::json one = readJson(dir + "/identify.json");
  const auto& b = one["base_parameters"];
  std::vector<double> rel;
  for (std::size_t i = 0; i < b["names"].size(); ++i) {
    const double t = b["truth"][i].get<double>();
    if (t != 0.0) rel.push_back(std::abs(b["ls"][i].get<double>() - t) / std::abs(t));
  }
  std::sort(rel.begin(), rel.end());
  EXPECT_LT(rel[rel.size() / 2], 0.02);
  EXPECT_EQ(readJson(dir + "/segmental.json")["stages"].size(), 3u);
  std::ifstream in(dir + "/report.md");
  const std::string report((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(report.find("| foot.Iyy |"), std::string::npos);
  EXPECT_NE(report.find("segmental lad"), std::string::npos);
  // The stages are validated on the same record as the one fit: their row has its RMS per joint.
  for (const char* method : {"| segmental ls |", "| segmental lad |"}) {
    const std::size_t row = report.find(method, report.find("## Summary"));
    ASSERT_NE(row, std::string::npos) << method;
    const std::string line = report.substr(row, report.find('\n', row) - row);
    EXPECT_EQ(line.find("| - |"), std::string::npos) << line;
  }
  EXPECT_FALSE(readJson(dir + "/segmental.json")["validation"].empty());
  EXPECT_NE(report.find("seed 4"), std::string::npos);
  EXPECT_EQ(report.find("/tmp"), std::string::npos) << "no absolute paths in the report";
  EXPECT_NE(stderrOf({"reproduce", "--design-restarts", "2", "--out", dir + "_y"}, 105).find("--excitation-knee"), std::string::npos);
}

// IDIM-IV on a chain: the controller from the record's metadata (exoid simulate writes it) or from
// a file of the same gains gives the same estimate; a file of the wrong size and a record without
// its reference are refused by name.
TEST(ChainCli, IdimIvReadsTheRigsControllerFromTheRecordOrAFile) {
  const std::string dir = ::testing::TempDir() + "/chain_idim_iv";
  std::filesystem::create_directories(dir);
  const std::string csv = dir + "/rec.csv", side = dir + "/rec.json";
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"simulate", "--model", "leg3", "--duration", "8", "--noise-q-deg", "0.02", "--noise-tau", "0.2", "--seed", "5",
                      "--out", csv}),
            0);
  ASSERT_EQ(runExoid({"identify", "--model", "leg3", "--data", csv, "--method", "ls,idim-iv", "--json", dir + "/meta.json"}), 0);
  // The sidecar's controller block is a --controller file as it stands.
  std::ofstream(dir + "/controller.json") << readJson(side)["controller"].dump();
  ASSERT_EQ(runExoid({"identify", "--model", "leg3", "--data", csv, "--method", "ls,idim-iv", "--controller", dir + "/controller.json",
                      "--json", dir + "/file.json"}),
            0);
  testing::internal::GetCapturedStdout();
  const nlohmann::json a = readJson(dir + "/meta.json")["methods"]["idim-iv"], b = readJson(dir + "/file.json")["methods"]["idim-iv"];
  EXPECT_EQ(a["status"], "converged") << a["message"];
  EXPECT_EQ(a["beta"], b["beta"]);  // %.17g in the metadata: the same gains, the same bytes
  std::ofstream(dir + "/two.json") << R"({"kp": [1, 2], "kd": [1, 2]})";
  EXPECT_NE(stderrOf({"identify", "--model", "leg3", "--data", csv, "--method", "idim-iv", "--controller", dir + "/two.json"}, 1)
                .find("'kp' must be an array of 3 numbers"),
            std::string::npos);
  // A record whose hip is locked (the segmental strategy's): refused, naming the metadata.
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"simulate", "--model", "leg3", "--duration", "3", "--lock", "hip", "--out", dir + "/locked.csv"}), 0);
  testing::internal::GetCapturedStdout();
  EXPECT_NE(stderrOf({"identify", "--model", "leg3", "--data", dir + "/locked.csv", "--method", "idim-iv"}, 1).find("locked_joints"),
            std::string::npos);
  // The record without q_ankle_ref: refused naming the column.
  std::ifstream in(csv);
  std::ofstream out(dir + "/no_ref.csv");
  std::string line;
  long drop = -1;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') {
      out << line << "\n";
      continue;
    }
    std::vector<std::string> cells;
    std::size_t start = 0;
    for (std::size_t comma; (comma = line.find(',', start)) != std::string::npos; start = comma + 1) cells.push_back(line.substr(start, comma - start));
    cells.push_back(line.substr(start));
    if (drop < 0) drop = std::find(cells.begin(), cells.end(), "q_ankle_ref") - cells.begin();
    std::string joined;
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (static_cast<long>(i) != drop) joined += (joined.empty() ? "" : ",") + cells[i];
    }
    out << joined << "\n";
  }
  out.close();
  EXPECT_NE(stderrOf({"identify", "--model", "leg3", "--data", dir + "/no_ref.csv", "--method", "idim-iv"}, 1).find("no 'q_ankle_ref' column"),
            std::string::npos);
}

// A vibrating stand through the CLI: the record carries the base IMU; identify fits the
// base-motion terms in the still base's parameters by default and, asked, in a moving base's
// (leg3's hip rotor inertia apart), exactly on exact data; asked without base motion, it refuses.
TEST(ChainCli, AVibratingStandIsFittedWithItsBaseMotion) {
  const std::string dir = ::testing::TempDir();
  const std::string csv = dir + "/leg3_vibrating.csv", side = dir + "/leg3_vibrating.json", still = dir + "/leg3_still.csv";
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"simulate", "--model", "leg3", "--duration", "10", "--vibration", "1", "--coulomb-v0", "0", "--record-derivatives",
                      "--imu-acc-noise", "0", "--imu-gyro-noise", "0", "--out", csv}),
            0);
  ASSERT_EQ(runExoid({"simulate", "--model", "leg3", "--duration", "2", "--out", still}), 0);
  ASSERT_EQ(runExoid({"identify", "--model", "leg3", "--data", csv, "--truth", side, "--json", dir + "/default.json"}), 0);
  ASSERT_EQ(runExoid({"identify", "--model", "leg3", "--data", csv, "--truth", side, "--moving-base-parameters", "--json", dir + "/moving.json"}), 0);
  testing::internal::GetCapturedStdout();
  EXPECT_EQ(readJson(dir + "/default.json")["base_parameters"]["names"].size(), 17u);
  const nlohmann::json moving = readJson(dir + "/moving.json");
  const nlohmann::json& b = moving["base_parameters"];
  ASSERT_EQ(b["names"].size(), 18u);
  EXPECT_NE(std::find(b["names"].begin(), b["names"].end(), "hip.Ia"), b["names"].end());
  for (std::size_t i = 0; i < 18; ++i) {
    const double truth = b["truth"][i].get<double>(), ls = b["ls"][i].get<double>();
    EXPECT_NEAR(ls, truth, 1e-6 * std::max(1.0, std::abs(truth))) << b["names"][i].get<std::string>();
  }
  EXPECT_NE(stderrOf({"identify", "--model", "leg3", "--data", still, "--moving-base-parameters"}, 1).find("no record carries base-motion terms"),
            std::string::npos);
}

// A chain from its URDF alone (no motors, no stand in the file) is simulated on the stand and
// identified exactly from the record with its base motion; the stand moves it.
TEST(ChainCli, AUrdfIsSimulatedOnAVibratingStandAndIdentifiedExactly) {
  const std::string dir = ::testing::TempDir(), urdf = std::string(EXOID_SOURCE_DIR) + "/models/leg3.urdf";
  const std::string csv = dir + "/urdf_vibrating.csv", side = dir + "/urdf_vibrating.json", out = dir + "/urdf_vibrating_fit.json";
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"simulate", "--model", urdf, "--duration", "10", "--vibration", "1", "--coulomb-v0", "0", "--record-derivatives",
                      "--imu-acc-noise", "0", "--imu-gyro-noise", "0", "--out", csv}),
            0);
  ASSERT_EQ(runExoid({"identify", "--model", urdf, "--data", csv, "--truth", side, "--json", out}), 0);
  testing::internal::GetCapturedStdout();
  std::ifstream in(csv);
  std::string line, header;
  double base_x_max = 0.0;
  std::size_t column = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream cells(line);
    std::string cell;
    if (header.empty()) {
      header = line;
      for (std::size_t k = 0; std::getline(cells, cell, ','); ++k) {
        if (cell == "base_x") column = k;
      }
      ASSERT_GT(column, 0u) << header;
      continue;
    }
    for (std::size_t k = 0; std::getline(cells, cell, ','); ++k) {
      if (k == column) base_x_max = std::max(base_x_max, std::abs(std::stod(cell)));
    }
  }
  EXPECT_GT(base_x_max, 1e-6);  // the stand sways (a rigid one stays at 0)
  const nlohmann::json r = readJson(out);
  const nlohmann::json& b = r["base_parameters"];
  ASSERT_FALSE(b["names"].empty());
  for (std::size_t i = 0; i < b["names"].size(); ++i) {
    const double truth = b["truth"][i].get<double>(), ls = b["ls"][i].get<double>();
    EXPECT_NEAR(ls, truth, 1e-6 * std::max(1.0, std::abs(truth))) << b["names"][i].get<std::string>();
  }
}

// The motor rig's feedback is the APAL rig's PID (core/pid.hpp): with an integral, the
// record carries ki and the PID law in its metadata, and IDIM-IV, whose instruments simulate that
// loop, stays exact on exact data. The APAL rig refuses the motor rig's options by name.
TEST(ChainCli, TheMotorRigTakesThePidsIntegral) {
  const std::string dir = ::testing::TempDir();
  const std::string csv = dir + "/leg3_pid.csv", side = dir + "/leg3_pid.json", out = dir + "/leg3_pid_fit.json";
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"simulate", "--model", "leg3", "--duration", "10", "--integral-hz", "0.5", "--coulomb-v0", "0", "--record-derivatives",
                      "--out", csv}),
            0);
  ASSERT_EQ(runExoid({"identify", "--model", "leg3", "--data", csv, "--truth", side, "--method", "idim-iv", "--json", out}), 0);
  testing::internal::GetCapturedStdout();
  const nlohmann::json c = readJson(side)["controller"];
  ASSERT_EQ(c["ki"].size(), 3u);
  for (std::size_t j = 0; j < 3; ++j) EXPECT_DOUBLE_EQ(c["ki"][j].get<double>(), c["kp"][j].get<double>() * 2.0 * M_PI * 0.5);
  const nlohmann::json r = readJson(out);
  const nlohmann::json& b = r["base_parameters"];
  const nlohmann::json& x = r["methods"]["idim-iv"]["beta"];
  for (std::size_t i = 0; i < b["names"].size(); ++i) {
    const double truth = b["truth"][i].get<double>();
    EXPECT_NEAR(x[i].get<double>(), truth, 1e-6 * std::max(1.0, std::abs(truth))) << b["names"][i].get<std::string>();
  }
}

// models/leg3.xml with its knee motor reflecting `kgm2` (the shipped 0.05 kg m^2 replaced), at `path`.
void writeLeg3WithKneeArmature(const std::string& path, const std::string& kgm2) {
  std::ifstream in(std::string(EXOID_SOURCE_DIR) + "/models/leg3.xml");
  std::string xml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string from = "damping=\"0.3\" armature=\"0.05\"";
  ASSERT_NE(xml.find(from), std::string::npos);
  xml.replace(xml.find(from), from.size(), "damping=\"0.3\" armature=\"" + kgm2 + "\"");
  std::ofstream(path) << xml;
}

// A URDF has no armature; a rig whose knee motor reflects 3 kg m^2, fitted without it, lies beyond
// --significance of any physical body (3.0 standard errors), though draws about the nearest one lie
// as far as often (several bounds active: not beyond the noise alone). The records show the
// armature itself: the failure names the term and its option; with it, the fit is consistent and usable.
TEST(ChainCli, AnArmatureTheUrdfLeavesOutIsNamedWithItsOption) {
  const std::string dir = ::testing::TempDir();
  ASSERT_NO_FATAL_FAILURE(writeLeg3WithKneeArmature(dir + "/leg3_heavy_rotor.xml", "3"));
  const std::string design = dir + "/arm_design.json", csv = dir + "/arm.csv", out = dir + "/arm.json";
  const std::string urdf = std::string(EXOID_SOURCE_DIR) + "/models/leg3.urdf";
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"excite", "--model", "leg3", "--restarts", "2", "--out", design}), 0);
  ASSERT_EQ(runExoid({"simulate", "--model", dir + "/leg3_heavy_rotor.xml", "--excitation", design, "--duration", "20", "--noise-tau", "0.3",
                      "--seed", "1", "--out", csv}),
            0);
  testing::internal::GetCapturedStdout();
  const std::string why = stderrOf({"identify", "--model", urdf, "--data", csv, "--json", out}, 3);
  EXPECT_NE(why.find("rerun with --armature knee"), std::string::npos) << why;
  EXPECT_NE(why.find("(the nearest physically consistent estimate to the data is"), std::string::npos) << why;
  const nlohmann::json knee = readJson(out)["optional_terms"]["armature"]["knee"];
  EXPECT_TRUE(knee["significant"].get<bool>());
  // Within 4 of its reported standard errors of the rig's 3 kg m^2.
  EXPECT_NEAR(knee["value_kgm2"].get<double>(), 3.0, 4.0 * knee["std_error_kgm2"].get<double>());
  testing::internal::CaptureStdout();
  EXPECT_EQ(runExoid({"identify", "--model", urdf, "--data", csv, "--armature", "knee,ankle"}), 0);
  testing::internal::GetCapturedStdout();
}

// The segmental strategy hides a missing armature (docs/findings.md, section 11): the knee stage,
// hip locked, folds a 10 kg m^2 rotor into shank.Iyy, and the later stage stays consistent. One fit
// of the last stage's records (every joint moving) is judged beside the stages and names it; on the
// same rig without the heavy rotor, identified with its own model, the stages stay usable. The
// comparison's numbers (stages_check.hpp) are checked in StagesCheck.*.
TEST(ChainCli, TheStagesNameATermAnEarlierStageAbsorbed) {
  const std::string dir = ::testing::TempDir() + "/absorbed";
  std::filesystem::create_directories(dir);
  ASSERT_NO_FATAL_FAILURE(writeLeg3WithKneeArmature(dir + "/heavy.xml", "10"));
  const std::string urdf = std::string(EXOID_SOURCE_DIR) + "/models/leg3.urdf";
  struct Rig {
    std::string simulated, identified, name;
    int exit_code;
  };
  for (const Rig& rig : {Rig{dir + "/heavy.xml", urdf, "heavy", 3}, Rig{"leg3", "leg3", "null", 0}}) {
    const std::string knee = dir + "/" + rig.name + "_knee.csv", all = dir + "/" + rig.name + "_all.csv", out = dir + "/" + rig.name + ".json";
    testing::internal::CaptureStdout();
    const std::vector<std::string> noisy = {"--duration", "10", "--noise-tau", "0.3", "--model", rig.simulated};
    std::vector<std::string> k = {"simulate", "--lock", "hip", "--seed", "20", "--out", knee}, a = {"simulate", "--seed", "21", "--out", all};
    k.insert(k.end(), noisy.begin(), noisy.end());
    a.insert(a.end(), noisy.begin(), noisy.end());
    ASSERT_EQ(runExoid(k), 0);
    ASSERT_EQ(runExoid(a), 0);
    testing::internal::GetCapturedStdout();
    const std::string why = stderrOf({"identify", "--model", rig.identified, "--stage", "knee=" + knee, "--data", all, "--json", out}, rig.exit_code);
    const nlohmann::json check = readJson(out)["against_one_fit"];
    ASSERT_TRUE(check["judged"].get<bool>()) << rig.name;
    if (rig.exit_code == 0) {
      EXPECT_LE(check["largest_abs_z"].get<double>(), check["threshold"].get<double>());
      EXPECT_TRUE(check["one_fit_consistent"].get<bool>());
      continue;
    }
    // The stages' own consistency passes; what names the rotor is the one fit beside them.
    EXPECT_EQ(why.find("no physically consistent body explains the data"), std::string::npos) << why;
    EXPECT_NE(why.find("one fit of the last stage's records"), std::string::npos) << why;
    EXPECT_NE(why.find("rerun with --armature knee"), std::string::npos) << why;
    EXPECT_FALSE(check["one_fit_consistent"].get<bool>());
    EXPECT_TRUE(check["armature"]["knee"]["significant"].get<bool>());
    // Without the consistency rules nothing is judged consistent: not judged, said as such.
    testing::internal::CaptureStdout();
    EXPECT_EQ(runExoid({"identify", "--model", rig.identified, "--stage", "knee=" + knee, "--data", all, "--no-consistency", "--json", out}), 0);
    EXPECT_NE(testing::internal::GetCapturedStdout().find("the one fit's consistency not judged (--no-consistency)"), std::string::npos);
    EXPECT_TRUE(readJson(out)["against_one_fit"]["one_fit_consistent"].is_null());
  }
}

// A record too short to choose a band from is refused naming its file, on every leg (one
// processing of a fit's records: fit_records.hpp).
TEST(ChainCli, ARecordTooShortForABandIsNamedOnEveryLeg) {
  const std::string dir = ::testing::TempDir();
  for (const std::string leg : {"apal", "leg3"}) {
    const std::string csv = dir + "/short_" + leg + ".csv", cut = dir + "/short_" + leg + "_cut.csv";
    testing::internal::CaptureStdout();
    ASSERT_EQ(runExoid({"simulate", "--model", leg, "--duration", "1", "--seed", "4", "--out", csv}), 0);
    testing::internal::GetCapturedStdout();
    // The metadata and the header, then 59 samples.
    std::ifstream in(csv);
    std::ofstream out(cut);
    int samples = 0;
    for (std::string line; std::getline(in, line) && samples < 60;) {
      out << line << '\n';
      if (line.rfind('#', 0) != 0) ++samples;
    }
    out.close();
    const std::string err = stderrOf({"identify", "--model", leg, "--data", cut}, 1);
    EXPECT_NE(err.find(cut + ": record too short to choose a band"), std::string::npos) << leg << ": " << err;
  }
}

// What identify reports as the band sensitivity, on both legs: each parameter's change, in its
// reported standard errors, when the record is refitted with the chosen cutoff a quarter wider;
// the same as a user's own refit with that cutoff given (--cutoff-hz), to rounding.
TEST(ChainCli, TheBandSensitivityIsTheRefitInAQuarterWiderBandOnEveryLeg) {
  const std::string dir = ::testing::TempDir();
  struct Leg {
    std::vector<std::string> model;  ///< --model M, or none (the APAL leg)
    std::string name;
  };
  for (const Leg& leg : {Leg{{}, "apal"}, Leg{{"--model", "leg3"}, "leg3"}}) {
    const std::string csv = dir + "/sensitivity_" + leg.name + ".csv", out = dir + "/sensitivity_" + leg.name + ".json",
                      wider_out = dir + "/sensitivity_" + leg.name + "_wider.json";
    const auto args = [&](std::vector<std::string> a) {
      a.insert(a.begin() + 1, leg.model.begin(), leg.model.end());
      return a;
    };
    testing::internal::CaptureStdout();
    ASSERT_EQ(runExoid(args({"simulate", "--duration", "10", "--seed", "4", "--out", csv})), 0);
    const int code = runExoid(args({"identify", "--data", csv, "--json", out}));
    const std::string printed = testing::internal::GetCapturedStdout();
    ASSERT_TRUE(code == 0 || code == 3) << leg.name;
    EXPECT_NE(printed.find("band sensitivity (every record's cutoff x1.25"), std::string::npos) << leg.name;
    const nlohmann::json j = readJson(out);
    const nlohmann::json& s = j["band_sensitivity"];
    ASSERT_EQ(s["cutoff_factor"].get<double>(), 1.25) << leg.name;
    const bool apal = leg.model.empty();
    const double cutoff = j["processing_per_record"][csv]["cutoff_hz"].get<double>();  // one form for every leg
    // The chosen band is well below the cap of a fifth of the 1 kHz rate.
    ASSERT_LT(1.25 * cutoff, 200.0) << leg.name;
    testing::internal::CaptureStdout();
    const int wider_code = runExoid(args({"identify", "--data", csv, "--cutoff-hz", core::formatNumber(1.25 * cutoff, 17), "--no-consistency", "--json", wider_out}));
    testing::internal::GetCapturedStdout();
    ASSERT_TRUE(wider_code == 0 || wider_code == 3) << leg.name;
    const nlohmann::json w = readJson(wider_out);
    std::vector<std::string> names;
    std::vector<double> fitted, wider, errors;
    if (apal) {
      const nlohmann::json& c = j["methods"]["ls"]["consistency"];
      for (const auto& [name, v] : c["unconstrained_parameters"].items()) {
        names.push_back(name);
        fitted.push_back(v.get<double>());
        errors.push_back(c["standard_errors"][name].get<double>());
        wider.push_back(w["parameters"][name].get<double>());
      }
    } else {
      names = j["base_parameters"]["names"].get<std::vector<std::string>>();
      fitted = j["base_parameters"]["ls"].get<std::vector<double>>();
      errors = j["base_parameters"]["std_error"].get<std::vector<double>>();
      wider = w["base_parameters"]["ls"].get<std::vector<double>>();
    }
    ASSERT_EQ(s["shift_standard_errors"].size(), names.size()) << leg.name;
    for (std::size_t i = 0; i < names.size(); ++i) {
      const double expected = (wider[i] - fitted[i]) / errors[i];
      EXPECT_NEAR(s["shift_standard_errors"][names[i]].get<double>(), expected, 1e-12 * std::max(1.0, std::abs(expected))) << leg.name << " " << names[i];
    }
  }
}

// identifiability --data on a chain, as on the APAL leg: every equation with every base parameter,
// then each joint's equation with what no joint below it has; relative to the simulation's
// sidecar. With the hip held, the knee's armature column is its link's inertia column (the knee
// accelerates only with itself): named as not identifiable, with the motion that would separate them.
TEST(ChainCli, IdentifiabilityOfARecordNamesWhatItCannotSeparate) {
  const std::string dir = ::testing::TempDir();
  const std::string csv = dir + "/leg3_held_hip.csv", out = dir + "/leg3_held_hip_identifiability.json";
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"simulate", "--model", "leg3", "--lock", "hip", "--duration", "6", "--seed", "2", "--out", csv}), 0);
  ASSERT_EQ(runExoid({"identifiability", "--model", "leg3", "--data", csv, "--json", out}), 0);
  testing::internal::GetCapturedStdout();
  const nlohmann::json j = readJson(out);
  EXPECT_NE(j["reference"]["origin"].get<std::string>().find("leg3_held_hip.json"), std::string::npos);
  ASSERT_EQ(j["blocks"].size(), 4u);
  EXPECT_EQ(j["blocks"][0]["block"], "all 3 equations, all 17");
  EXPECT_EQ(j["blocks"][2]["block"], "knee equation, params 6-11");
  EXPECT_EQ(j["blocks"][2]["unidentifiable"], nlohmann::json::array({"knee.Ia"}));
  EXPECT_EQ(j["blocks"][3]["unidentifiable"], nlohmann::json::array());
  std::string advice;
  for (const auto& line : j["blocks"][2]["advice"]) advice += line.get<std::string>() + "\n";
  EXPECT_NE(advice.find("knee.Ia cannot be identified from this record"), std::string::npos) << advice;
  EXPECT_NE(advice.find("accelerating differently from the joints above it"), std::string::npos) << advice;
  // The APAL leg reads --armature as its own (knee: Ia2); a hip armature, which Jt absorbs, is refused.
  EXPECT_NE(stderrOf({"identifiability", "--data", csv, "--armature", "hip"}, 105).find("absorbs"), std::string::npos);
}

// As on the APAL leg: wall times and PSO's best-cost histories only when asked (--timing,
// --history), so the same input gives the same bytes; each method's JSON says what the APAL leg's
// says of it (iterations, L1 cost, its box, the optimality gaps), in one fit and in every stage.
TEST(ChainCli, WallTimesAndHistoriesOnlyWhenAskedAndTheBytesRepeat) {
  const std::string dir = ::testing::TempDir() + "/chain_timing";
  std::filesystem::create_directories(dir);
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"simulate", "--model", "leg3", "--duration", "4", "--seed", "6", "--out", dir + "/r.csv"}), 0);
  const std::vector<std::string> identify = {"identify", "--model", "leg3", "--data", dir + "/r.csv", "--method", "ls,pso", "--pso-iterations", "50"};
  const auto run = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args = identify;
    args.insert(args.end(), {"--json", out});
    args.insert(args.end(), extra.begin(), extra.end());
    const int rc = runExoid(args);  // 3 or 0: PSO's 50 iterations may end on its box
    EXPECT_TRUE(rc == 0 || rc == 3) << rc;
    std::ifstream in(out);
    const std::string text(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>{});
    EXPECT_FALSE(text.empty()) << out;
    return text;
  };
  const std::string first = run(dir + "/a.json", {}), second = run(dir + "/b.json", {});
  const nlohmann::json asked = nlohmann::json::parse(run(dir + "/c.json", {"--timing", "--history"}));
  const nlohmann::json staged = nlohmann::json::parse(
      run(dir + "/d.json", {"--stage", "knee=" + dir + "/r.csv", "--timing", "--history"}));
  const std::string staged_plain = run(dir + "/e.json", {"--stage", "knee=" + dir + "/r.csv"});
  testing::internal::GetCapturedStdout();
  EXPECT_EQ(staged_plain.find("wall_time_s"), std::string::npos);
  EXPECT_EQ(staged_plain.find("best_cost_history"), std::string::npos);
  EXPECT_EQ(first, second);
  EXPECT_EQ(first.find("wall_time_s"), std::string::npos);
  EXPECT_EQ(first.find("best_cost_history"), std::string::npos);
  const nlohmann::json& pso = asked["methods"]["pso"];
  // The initial swarm's best, then one per iteration.
  EXPECT_EQ(pso["best_cost_history"].size(), pso["iterations"].get<std::size_t>() + 1) << pso.dump().substr(0, 300);
  EXPECT_GE(pso["wall_time_s"].get<double>(), 0.0);
  EXPECT_GE(asked["base_parameters"]["wall_time_s"].get<double>(), 0.0);
  EXPECT_EQ(pso["box"]["lower"].size(), 17u);
  EXPECT_LE(pso["box"]["lower"][0].get<double>(), pso["beta"][0].get<double>());
  // On a noisy record the stages' refit in the wider band moves the estimate (it did refit).
  double moved = 0.0;
  for (const auto& [name, shift] : staged.at("band_sensitivity").at("shift_standard_errors").items()) moved = std::max(moved, std::abs(shift.get<double>()));
  EXPECT_GT(moved, 1e-3);
  ASSERT_EQ(staged.at("stages").size(), 2u);
  for (const auto& stage : staged.at("stages")) {
    EXPECT_FALSE(stage.at("methods").at("pso").at("best_cost_history").empty()) << stage.dump().substr(0, 300);
    EXPECT_TRUE(stage.at("methods").at("ls").contains("wall_time_s"));
  }
}

// A stage's record designed for a chain, as for the APAL leg's knee-only one: the hip held where
// the design says, the knee armature (its column is the shank's inertia's while the hip is held)
// named as not separable, the rest well conditioned; simulate locks the hip there.
TEST(ChainCli, ExciteDesignsAStageRecordOfAChain) {
  const std::string dir = ::testing::TempDir();
  const std::string design = dir + "/leg3_stage_design.json", csv = dir + "/leg3_stage.csv";
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"excite", "--model", "leg3", "--first-moving", "knee", "--held-at-deg", "5", "--restarts", "1", "--max-evaluations",
                      "400", "--no-plot", "--out", design}),
            0);
  ASSERT_EQ(runExoid({"simulate", "--model", "leg3", "--excitation", design, "--duration", "2", "--out", csv}), 0);
  testing::internal::GetCapturedStdout();
  const nlohmann::json d = readJson(design);
  EXPECT_EQ(d["options"]["held_joints"], nlohmann::json::array({"hip"}));
  EXPECT_DOUBLE_EQ(d["options"]["held_at_rad"][0].get<double>(), 5.0 * M_PI / 180.0);
  EXPECT_EQ(d["comparison"]["not_separable"], nlohmann::json::array({"knee.Ia"}));
  EXPECT_FALSE(d["comparison"]["crb_std"].contains("knee.Ia"));
  EXPECT_FALSE(d["comparison"]["crb_std"].contains("hip.fc"));  // the held hip's own equation is not in the record
  // Inseparable columns left in make it singular (condition 5.5e15 before they were left out); a
  // separable set scores as designs of every joint do (< 10), with room for this short search.
  EXPECT_LT(d["score"]["condition_number"].get<double>(), 100.0);
  // The design holds the hip at 5 deg, and the rig's lock holds it there.
  const nlohmann::json& hip = d["trajectory"]["joints"][0];
  EXPECT_EQ(hip["name"], "hip");
  EXPECT_DOUBLE_EQ(hip["offset_rad"].get<double>(), 5.0 * M_PI / 180.0);
  for (const char* c : {"cos_rad", "sin_rad"}) {
    for (const auto& v : hip[c]) EXPECT_EQ(v.get<double>(), 0.0) << c;
  }
  std::ifstream in(csv);
  std::string line, header;
  bool locked = false;
  double worst = 0.0;
  while (std::getline(in, line)) {
    if (line.rfind("# locked_joints: hip", 0) == 0) locked = true;
    if (line.empty() || line[0] == '#') continue;
    if (header.empty()) {
      header = line;
      continue;
    }
    // Each sample's q_hip_true, found by its name.
    std::stringstream names(header), cells(line);
    std::string name, cell;
    while (std::getline(names, name, ',') && std::getline(cells, cell, ',')) {
      if (name == "q_hip_true") worst = std::max(worst, std::abs(std::stod(cell) - 5.0 * M_PI / 180.0));
    }
  }
  EXPECT_TRUE(locked);
  EXPECT_LT(worst, 1e-5);  // the lock holds it within 1e-5 rad (sim/motor_rig.hpp)
  // What is not a joint, or outside the joint's range, is refused naming the option (and writes nothing).
  std::filesystem::remove(dir + "/x.json");
  EXPECT_NE(stderrOf({"excite", "--model", "leg3", "--first-moving", "toe", "--out", dir + "/x.json"}, 105).find("hip, knee, ankle"),
            std::string::npos);
  EXPECT_NE(stderrOf({"excite", "--model", "leg3", "--first-moving", "knee", "--held-at-deg", "500", "--out", dir + "/x.json"}, 105)
                .find("--held-at-deg"),
            std::string::npos);
  EXPECT_NE(stderrOf({"excite", "--armature", "knee", "--out", dir + "/x.json"}, 105).find("--armature"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.json"));
}

// identify --plot on every leg: the figure, and its series, whose predicted - measured RMS per joint
// is the validation's in the JSON (computed apart, from the same rows).
TEST(ChainCli, TheFitsFigureIsDrawnOnEveryLeg) {
  const std::string dir = ::testing::TempDir() + "/plot_";
  struct Leg {
    std::string model;
    std::vector<std::string> joints, fit, check;
  };
  const Leg legs[] = {{"apal", {"hip", "knee"}, {"--trajectory", "3"}, {"--trajectory", "4", "--seed", "2"}},
                      {"leg3", {"hip", "knee", "ankle"}, {"--seed", "1"}, {"--seed", "2"}}};
  for (const Leg& leg : legs) {
    const std::string fit = dir + leg.model + "_fit.csv", check = dir + leg.model + "_check.csv", png = dir + leg.model + ".png",
                      json = dir + leg.model + ".json";
    std::vector<std::string> a = {"simulate", "--model", leg.model, "--duration", "4", "--out", fit}, b = {"simulate", "--model", leg.model, "--duration", "4", "--out", check};
    a.insert(a.end(), leg.fit.begin(), leg.fit.end());
    b.insert(b.end(), leg.check.begin(), leg.check.end());
    testing::internal::CaptureStdout();
    ASSERT_EQ(runExoid(a), 0);
    ASSERT_EQ(runExoid(b), 0);
    const int code = runExoid({"identify", "--model", leg.model, "--data", fit, "--validate", check, "--plot", png, "--json", json});
    testing::internal::GetCapturedStdout();
    ASSERT_TRUE(code == 0 || code == 3) << leg.model;
    ASSERT_TRUE(std::filesystem::exists(png)) << leg.model;
    std::ifstream in(dir + leg.model + "_series.csv");
    std::string line;
    std::getline(in, line);
    std::vector<double> sum(leg.joints.size(), 0.0);
    std::size_t n = 0;
    while (std::getline(in, line)) {
      std::stringstream cells(line);
      std::string cell;
      std::getline(cells, cell, ',');  // t_s
      for (std::size_t j = 0; j < leg.joints.size(); ++j) {
        std::getline(cells, cell, ',');
        const double measured = std::stod(cell);
        std::getline(cells, cell, ',');
        sum[j] += (std::stod(cell) - measured) * (std::stod(cell) - measured);
      }
      ++n;
    }
    ASSERT_GT(n, 50u) << leg.model;  // the rows as fitted: decimated in the band chosen from the record
    const nlohmann::json r = readJson(json);
    for (std::size_t j = 0; j < leg.joints.size(); ++j) {
      const double json_rms = leg.model == "apal" ? r["methods"]["ls"]["validation"][check][leg.joints[j]]["rms_Nm"].get<double>()
                                                  : r["validation"][0]["joints"][j]["rms_error_Nm"].get<double>();
      // The series holds 9 significant digits of torques of tens of N m.
      EXPECT_NEAR(std::sqrt(sum[j] / static_cast<double>(n)), json_rms, 1e-6 * (1.0 + json_rms)) << leg.model << " " << leg.joints[j];
    }
  }
}

TEST(ChainCli, WhatTheChainPathDoesNotTakeIsRefusedByName) {
  const std::string dir = ::testing::TempDir();
  EXPECT_NE(stderrOf({"excite", "--model", "leg3", "--knee-only", "--out", dir + "/x.json"}, 105).find("--knee-only"), std::string::npos);
  EXPECT_NE(stderrOf({"identify", "--model", "leg3", "--thigh-length", "0.4", "--data", std::string(EXOID_SOURCE_DIR) + "/models/leg3.urdf"}, 105)
                .find("--thigh-length"),
            std::string::npos);
  // IDIM-IV fits one record whole (its instruments simulate that record's closed loop): not stage by stage.
  const std::string urdf = std::string(EXOID_SOURCE_DIR) + "/models/leg3.urdf";
  EXPECT_NE(stderrOf({"identify", "--model", "leg3", "--method", "idim-iv", "--stage", "knee=" + urdf, "--data", urdf}, 105)
                .find("needs one fit of --data (no --stage)"),
            std::string::npos);
}

}  // namespace
}  // namespace exoid::experiments
