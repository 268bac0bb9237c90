// `exoid identifiability --model`: a robot model's base parameters through the real command line.
#include "cli_test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

namespace exoid::experiments {
namespace {

using exoid::test::runExoid;

nlohmann::json reportOf(const std::string& model) {
  const std::string json = ::testing::TempDir() + "/model_report_" + model + ".json";
  testing::internal::CaptureStdout();
  const int rc = runExoid({"identifiability", "--model", model, "--json", json});
  testing::internal::GetCapturedStdout();
  EXPECT_EQ(rc, 0);
  std::ifstream in(json);
  return nlohmann::json::parse(in);
}

TEST(ModelReport, ApalLegsBaseParametersAreThePapersX) {
  const nlohmann::json j = reportOf("apal");
  const nlohmann::json& b = j["base_parameters"];
  ASSERT_EQ(b["rank"], 10);
  // The paper's set B (docs/paper.md): X = [5.83, 2.60, 3.4545, 1.5, 0.6, 1.28, -0.32, 0.5952, 0.35, 0.25],
  // here as the QR's basis: -Myt, -Mxt, Jt - Js, fc1, fv1, -Mys, -Mxs, Js, fc2, fv2.
  const double expected[] = {-2.60, -5.83, 3.4545 - 0.5952, 1.5, 0.6, 0.32, -1.28, 0.5952, 0.35, 0.25};
  for (int i = 0; i < 10; ++i) EXPECT_NEAR(b["parameters"][i]["true_value"].get<double>(), expected[i], 1e-9) << i;
  EXPECT_EQ(b["parameters"][1]["name"], "thigh.mz + 1 term");  // a short label; the combination written out
  EXPECT_EQ(b["parameters"][1]["combination"], "thigh.mz - 0.45 shank.m");
  EXPECT_FALSE(j["model"]["left_out"].empty());  // the four-bar's cylinder and rod, named
}

TEST(ModelReport, Leg3HasSeventeenBaseParameters) {
  const nlohmann::json j = reportOf("leg3");
  EXPECT_EQ(j["model"]["joints"].size(), 3u);
  // 3 links x (mx, mz, Iyy), 3 joints x (fc, fv), knee and ankle armature (the hip's regroups
  // into the thigh's Iyy: its base does not move).
  EXPECT_EQ(j["base_parameters"]["rank"], 17);
}

TEST(ModelReport, NeitherDataNorModelIsAnError) {
  testing::internal::CaptureStderr();
  EXPECT_NE(runExoid({"identifiability"}), 0);
  EXPECT_NE(testing::internal::GetCapturedStderr().find("--model"), std::string::npos);
}

}  // namespace
}  // namespace exoid::experiments
