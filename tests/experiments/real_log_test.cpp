// Real logs end to end: the DFKI double pendulum's raw swing-up log (gzipped, unmodified, irregular
// timestamps, its own column names) + the shipped profile -> exoid identify -> the lab's own
// inertial parameters, derived here from the lab's parameter file (data/real/dfki_double_pendulum).
#include "cli_test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace exoid::experiments {
namespace {

using exoid::test::runExoid;

const std::string kDir = std::string(EXOID_SOURCE_DIR) + "/data/real/dfki_double_pendulum/";

// "key: value" lines of the lab's design_A0_model_2.0_parameters.yml.
std::map<std::string, double> labParameters() {
  std::ifstream in(kDir + "design_A0_model_2.0_parameters.yml");
  std::map<std::string, double> p;
  std::string line;
  while (std::getline(in, line)) {
    const auto colon = line.find(':');
    if (colon != std::string::npos) p[line.substr(0, colon)] = std::stod(line.substr(colon + 1));
  }
  return p;
}

nlohmann::json identify(const std::vector<std::string>& extra, int expected_exit = 0) {
  const std::string out = ::testing::TempDir() + "/real_log.json";
  std::vector<std::string> args = {"identify", "--profile", kDir + "profile.toml", "--method", "ls", "--json", out};
  args.insert(args.end(), extra.begin(), extra.end());
  testing::internal::CaptureStdout();
  EXPECT_EQ(runExoid(args), expected_exit);
  testing::internal::GetCapturedStdout();
  std::ifstream in(out);
  return nlohmann::json::parse(in);
}

TEST(RealLog, SwingUpGivesTheLabsInertialParametersWithinTenPercent) {
  const std::map<std::string, double> lab = labParameters();
  ASSERT_GT(lab.size(), 10u);
  const double m1 = lab.at("m1"), m2 = lab.at("m2"), r1 = lab.at("r1"), r2 = lab.at("r2"), l1 = lab.at("l1");
  const double I1 = lab.at("I1"), I2 = lab.at("I2"), Ir = lab.at("Ir"), gr = lab.at("gr");
  // The lab's model mapped to X (README of the data): the rotor inertia enters the diagonal.
  const std::map<std::string, double> truth = {{"Mxt", m1 * r1 + m2 * l1},
                                               {"Jt", I1 + I2 + m2 * l1 * l1 + (gr * gr + 1) * Ir},
                                               {"Mxs", m2 * r2},
                                               {"Js", I2 + gr * gr * Ir}};
  const nlohmann::json j = identify({"--data", kDir + "design_A0_20220815_trajectory_11.csv.gz"});
  EXPECT_EQ(j["status"], "usable");
  EXPECT_DOUBLE_EQ(j["constants"]["thigh_length_m"].get<double>(), 0.3);  // from the profile
  const auto& sampling = j["inputs"]["sampling"].begin().value();
  EXPECT_TRUE(sampling["resampled"].get<bool>());  // the raw log's intervals run 1.2-3.8 ms
  for (const auto& [name, value] : truth) {
    const double x = j["parameters"][name].get<double>();
    EXPECT_LT(std::abs(x - value) / value, 0.10) << name << ": " << x << " against the lab's " << value;
  }
}

TEST(RealLog, SeveralRecordsAreProcessedOneByOneThenFittedTogether) {
  const std::string rec = kDir + "design_A0_20220815_trajectory_11.csv.gz";
  const nlohmann::json one = identify({"--data", rec});
  const nlohmann::json two = identify({"--data", rec, "--data", rec});
  // The same record twice: the same rows twice, so the same least-squares estimate (gluing the
  // two end to end would put a jump through the filter instead).
  for (const auto& [name, v] : one["parameters"].items()) {
    EXPECT_NEAR(two["parameters"][name].get<double>(), v.get<double>(), 1e-9 * (1.0 + std::abs(v.get<double>()))) << name;
  }
  EXPECT_EQ(two["inputs"]["data"].size(), 2u);
}

TEST(RealLog, WithoutTheThighLengthIdentifyRefusesAndSaysHow) {
  // Columns mapped by flags, no profile: nothing gives Lt.
  testing::internal::CaptureStderr();
  EXPECT_EQ(runExoid({"identify", "--data", kDir + "design_A0_20220815_trajectory_11.csv.gz", "--columns",
                      "t=time,q_hip=pos_meas1,q_knee=pos_meas2,tau_hip=tau_meas1,tau_knee=tau_meas2"}),
            1);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("--thigh-length"), std::string::npos) << err;
  EXPECT_NE(err.find("thigh_length_m"), std::string::npos) << err;
}

}  // namespace
}  // namespace exoid::experiments
