#include "exoid/sim/sidecar.hpp"

#include "test_support.hpp"

#include <cstdio>
#include <fstream>

namespace exoid::sim {
namespace {

class SidecarTest : public test::MujocoTest {};

TEST_F(SidecarTest, CarriesProvenanceSettingsAndTruths) {
  SimConfig c;
  c.trajectory = 1;
  c.duration_s = 1.0;
  c.seed = 42;
  c.sensors.noise_tau_Nm = 0.5;
  const SimResult r = simulate(c);
  const nlohmann::json j = sidecar(r, "0.1.0-test");
  EXPECT_EQ(j["exoid_version"], "0.1.0-test");
  EXPECT_EQ(j["mujoco_version"], "2.2.2");
  EXPECT_EQ(j["model"]["fnv1a64"], toHex(fnv1a64(readFileBytes(defaultModelPath()))));
  EXPECT_EQ(j["model"]["path"], defaultModelPath());
  EXPECT_EQ(j["seed"], 42u);
  EXPECT_EQ(j["settings"]["sensors"]["noise_tau_Nm"], 0.5);
  EXPECT_EQ(j["settings"]["trajectory_spec"]["locked_joints"], 1);
  EXPECT_EQ(j["truth"]["rigid"]["parameters"]["Jt"], r.truth.x[2]);
  EXPECT_NEAR(j["truth"]["rigid"]["parameters"]["Mxt"].get<double>(), 5.83, 1e-9);
  EXPECT_EQ(j["truth"]["thigh_length_m"], 0.45);
  EXPECT_TRUE(j["truth"]["lumped_band"]["min"].contains("Mys"));
  EXPECT_TRUE(j["truth"]["friction"].contains("v0_radps"));
  EXPECT_TRUE(j["stats"]["tracking_error_deg"]["knee"].contains("rms"));
  EXPECT_EQ(j["columns"].size(), r.table.names.size());
  const std::string path = test::scratchPath("sidecar.json");
  writeJson(j, path);
  std::ifstream in(path);
  EXPECT_EQ(nlohmann::json::parse(in), j);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace exoid::sim
