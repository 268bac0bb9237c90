// `exoid simulate`'s rig options on every leg, one spelling each (the APAL leg's own options are its
// aliases): the torque sensor's bias, the actuators' bandwidth, the feedforward, the lock and the
// feedback's integral, checked on what the simulator recorded.
#include "cli_test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace exoid::experiments {
namespace {

using exoid::test::readJson;
using exoid::test::runExoid;
using exoid::test::slurp;

// A simulated record: its metadata lines ("# key: value") and its columns by name.
struct Record {
  std::map<std::string, std::string> metadata;
  std::map<std::string, std::vector<double>> columns;
};

Record readRecord(const std::string& path) {
  std::ifstream in(path);
  Record r;
  std::string line;
  std::vector<std::string> names;
  while (std::getline(in, line)) {
    if (line.rfind("# ", 0) == 0) {
      const std::size_t colon = line.find(": ");
      if (colon != std::string::npos) r.metadata[line.substr(2, colon - 2)] = line.substr(colon + 2);
      continue;
    }
    std::stringstream cells(line);
    std::string cell;
    if (names.empty()) {
      while (std::getline(cells, cell, ',')) names.push_back(cell);
      continue;
    }
    for (std::size_t k = 0; std::getline(cells, cell, ','); ++k) r.columns[names.at(k)].push_back(std::stod(cell));
  }
  return r;
}

// exoid simulate of 0.5 s into `out`; its exit code, and its stderr into `err` when given.
int simulate(std::vector<std::string> args, const std::string& out, std::string* err = nullptr) {
  args.insert(args.begin(), "simulate");
  for (const std::string& s : {std::string("--duration"), std::string("0.5"), std::string("--out"), out}) args.push_back(s);
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  const int code = runExoid(args);
  testing::internal::GetCapturedStdout();
  const std::string e = testing::internal::GetCapturedStderr();
  if (err) *err = e;
  return code;
}

// The option is refused (a usage error) and the message names it.
void expectRefused(const std::vector<std::string>& args, const std::string& option) {
  std::string err;
  EXPECT_EQ(simulate(args, ::testing::TempDir() + "/rig_refused.csv", &err), 105) << option;
  EXPECT_NE(err.find(option), std::string::npos) << err;
}

struct Leg {
  const char* model;
  std::vector<std::string> joints;
};

const Leg kLegs[] = {{"apal", {"hip", "knee"}}, {"leg3", {"hip", "knee", "ankle"}}};

// With an ideal, noiseless torque sensor the recorded torque is the joint's plus the bias: exactly.
TEST(RigOptions, TheTorqueBiasIsAddedToEveryJointsSensorOnEveryLeg) {
  for (const Leg& leg : kLegs) {
    const std::string csv = ::testing::TempDir() + "/rig_bias_" + leg.model + ".csv";
    std::vector<std::string> bias = {"0.5", "-1.25", "2"};
    bias.resize(leg.joints.size());
    std::string list;
    for (const std::string& b : bias) list += (list.empty() ? "" : ",") + b;
    ASSERT_EQ(simulate({"--model", leg.model, "--tau-bias", list, "--noise-tau", "0", "--torque-sensor-bandwidth", "0"}, csv), 0) << leg.model;
    const Record r = readRecord(csv);
    for (std::size_t j = 0; j < leg.joints.size(); ++j) {
      const std::vector<double>& measured = r.columns.at("tau_" + leg.joints[j]);
      const std::vector<double>& truth = r.columns.at("tau_" + leg.joints[j] + "_true");
      ASSERT_EQ(measured.size(), truth.size());
      double worst = 0.0, largest = 0.0;
      for (std::size_t k = 0; k < measured.size(); ++k) {
        worst = std::max(worst, std::abs(measured[k] - truth[k] - std::stod(bias[j])));
        largest = std::max(largest, std::abs(truth[k]));
      }
      // The file holds 9 significant digits or more: the difference is the bias to those digits.
      EXPECT_LE(worst, 1e-8 * (1.0 + largest)) << leg.model << " " << leg.joints[j];
    }
  }
  const std::string csv = ::testing::TempDir() + "/rig_bias_count.csv";
  testing::internal::CaptureStderr();
  EXPECT_EQ(runExoid({"simulate", "--model", "leg3", "--tau-bias", "1,2", "--out", csv}), 105);
  EXPECT_NE(testing::internal::GetCapturedStderr().find("--tau-bias: expected one bias per joint (3)"), std::string::npos);
}

// The APAL leg's own spellings are aliases of the options every leg takes: the same bytes.
TEST(RigOptions, TheApalLegsOwnSpellingsAreAliases) {
  const std::string dir = ::testing::TempDir() + "/rig_alias_";
  ASSERT_EQ(simulate({"--tau-bias", "0.5,-0.25", "--actuator-bandwidth", "30"}, dir + "a.csv"), 0);
  ASSERT_EQ(simulate({"--tau-bias-hip", "0.5", "--tau-bias-knee", "-0.25", "--hip-actuator-bandwidth", "30", "--knee-actuator-bandwidth", "30"},
                     dir + "b.csv"),
            0);
  EXPECT_EQ(slurp(dir + "a.csv"), slurp(dir + "b.csv"));
  const std::vector<std::string> fourier = {"--fourier-hip", "-10", "--fourier-knee", "60,10,5"};
  std::vector<std::string> lock = fourier, lock_hip = fourier;
  lock.insert(lock.end(), {"--lock", "hip"});
  lock_hip.push_back("--lock-hip");
  ASSERT_EQ(simulate(lock, dir + "c.csv"), 0);
  ASSERT_EQ(simulate(lock_hip, dir + "d.csv"), 0);
  EXPECT_EQ(slurp(dir + "c.csv"), slurp(dir + "d.csv"));
  EXPECT_EQ(readRecord(dir + "c.csv").metadata.at("hip_locked"), "true");
  // What the APAL rig cannot do is refused by name: its knee has no lock, the paper's trajectories
  // hold no offset (either spelling), and an option with its alias is given twice.
  expectRefused({"--lock", "knee"}, "--lock");
  expectRefused({"--lock", "hip"}, "--lock");
  expectRefused({"--lock-hip"}, "--lock-hip");
  expectRefused({"--tau-bias", "1,1", "--tau-bias-hip", "1"}, "--tau-bias");
  std::vector<std::string> both = lock;
  both.push_back("--lock-hip");
  expectRefused(both, "--lock");
}

// A chain's rig: the actuators' bandwidth in the record, a joint locked once, the integral below
// the position loop's bandwidth.
TEST(RigOptions, AChainsActuatorsLocksAndIntegralAreCheckedAndRecorded) {
  const std::string csv = ::testing::TempDir() + "/rig_chain_actuators.csv";
  ASSERT_EQ(simulate({"--model", "leg3", "--actuator-bandwidth", "40"}, csv), 0);
  EXPECT_EQ(readRecord(csv).metadata.at("actuator_bandwidth_Hz"), "40");
  expectRefused({"--model", "leg3", "--lock", "hip,hip"}, "--lock");
  expectRefused({"--model", "leg3", "--integral-hz", "5"}, "--integral-hz");
}

// The feedback's integral on every leg: ki = kp 2 pi f per joint, in the record's controller metadata.
TEST(RigOptions, TheIntegralIsEveryLegsAndInTheRecord) {
  for (const Leg& leg : kLegs) {
    const std::string csv = ::testing::TempDir() + "/rig_integral_" + leg.model + ".csv";
    ASSERT_EQ(simulate({"--model", leg.model, "--integral-hz", "0.25"}, csv), 0) << leg.model;
    const Record r = readRecord(csv);
    std::stringstream kp(r.metadata.at("controller_kp_Nm_per_rad")), ki(r.metadata.at("controller_ki_Nm_per_rad_s"));
    std::string p, i;
    std::size_t joints = 0;
    while (std::getline(kp, p, ',') && std::getline(ki, i, ',')) {
      EXPECT_NEAR(std::stod(i), std::stod(p) * 2.0 * M_PI * 0.25, 1e-9 * std::stod(i)) << leg.model;
      ++joints;
    }
    EXPECT_EQ(joints, leg.joints.size()) << leg.model;
  }
}

// Without the feedforward the feedback alone tracks, on every leg: worse, and said in the record
// (IDIM-IV's controller reads it).
TEST(RigOptions, WithoutFeedforwardTheFeedbackAloneTracksOnEveryLeg) {
  for (const Leg& leg : kLegs) {
    const std::string with = ::testing::TempDir() + "/rig_ff_" + leg.model + ".csv", without = ::testing::TempDir() + "/rig_noff_" + leg.model + ".csv";
    ASSERT_EQ(simulate({"--model", leg.model}, with), 0);
    ASSERT_EQ(simulate({"--model", leg.model, "--no-feedforward"}, without), 0);
    const Record a = readRecord(with), b = readRecord(without);
    EXPECT_EQ(a.metadata.at("feedforward"), "true") << leg.model;
    EXPECT_EQ(b.metadata.at("feedforward"), "false") << leg.model;
    const auto rms = [&](const Record& r) {
      double s = 0.0;
      std::size_t n = 0;
      for (const std::string& j : leg.joints) {
        const std::vector<double>& q = r.columns.at("q_" + j + "_true");
        const std::vector<double>& ref = r.columns.at("q_" + j + "_ref");
        for (std::size_t k = 0; k < q.size(); ++k, ++n) s += (q[k] - ref[k]) * (q[k] - ref[k]);
      }
      return std::sqrt(s / static_cast<double>(n));
    };
    EXPECT_GT(rms(b), 2.0 * rms(a)) << leg.model;
  }
  const nlohmann::json side = readJson(::testing::TempDir() + "/rig_noff_leg3.json");
  EXPECT_EQ(side["controller"]["feedforward"], "none");
}

}  // namespace
}  // namespace exoid::experiments
