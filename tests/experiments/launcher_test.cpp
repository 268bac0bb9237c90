// `exoid` is built without the simulator and runs identify and identifiability on logs itself;
// everything else it hands to exoid-full. Checked on the built binaries: what the dynamic loader
// loads for `exoid`, that it identifies a real log with exoid-full absent, and that a simulator
// command then says what is missing.
#include "exoid/experiments/commands/launcher.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

namespace exoid::experiments {
namespace {

namespace fs = std::filesystem;

const std::string kLogDir = std::string(EXOID_SOURCE_DIR) + "/data/real/dfki_double_pendulum/";

struct Outcome {
  int rc;
  std::string text;
};

// A shell command's exit code and its stdout and stderr together.
Outcome shell(const std::string& command) {
  std::string text;
  FILE* p = ::popen((command + " 2>&1").c_str(), "r");
  if (!p) return {-1, "popen failed"};
  std::array<char, 4096> buf{};
  while (const std::size_t n = std::fread(buf.data(), 1, buf.size(), p)) text.append(buf.data(), n);
  const int status = ::pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text};
}

TEST(Launcher, OnlyLogCommandsWithoutAModelStayInTheLightBinary) {
  EXPECT_FALSE(needsFullBinary({"identify", "--data", "a.csv", "--method", "ls"}));
  EXPECT_FALSE(needsFullBinary({"identifiability", "--data", "a.csv"}));
  EXPECT_TRUE(needsFullBinary({}));
  EXPECT_TRUE(needsFullBinary({"--help"}));
  EXPECT_TRUE(needsFullBinary({"simulate", "--out", "a.csv"}));
  EXPECT_TRUE(needsFullBinary({"identify", "--help"}));
  EXPECT_TRUE(needsFullBinary({"identify", "--data", "a.csv", "--model", "leg3"}));
  EXPECT_TRUE(needsFullBinary({"identify", "--data", "a.csv", "--model=leg3"}));
  EXPECT_TRUE(needsFullBinary({"identifiability", "--model", "apal"}));
  EXPECT_TRUE(needsFullBinary({"identify", "--stage", "knee=a.csv", "--data", "b.csv"}));
  EXPECT_TRUE(needsFullBinary({"identify", "--data", "a.csv", "--plot", "p.png"}));
  // A chain's own options go to the binary that knows them, which refuses them for the APAL leg by name.
  for (const char* chain_only : {"--moving-base-parameters", "--consistency-draws", "--consistency-seed"}) {
    EXPECT_TRUE(needsFullBinary({"identify", "--data", "a.csv", chain_only, "50"})) << chain_only;
  }
  for (const std::string& c : simulatorCommands()) EXPECT_TRUE(needsFullBinary({c})) << c;
}

TEST(Launcher, ExoidLoadsNoSimulatorRendererOrUrdfLibrary) {
  // The dynamic loader's own list (what ldd prints): exoid starts without them.
  const Outcome o = shell("LD_TRACE_LOADED_OBJECTS=1 " + std::string(EXOID_BINARY));
  ASSERT_EQ(o.rc, 0) << o.text;
  ASSERT_NE(o.text.find("libc.so"), std::string::npos) << o.text;
  for (const char* heavy : {"mujoco", "OSMesa", "libGL", "avcodec", "avformat", "urdfdom", "console_bridge"}) {
    EXPECT_EQ(o.text.find(heavy), std::string::npos) << heavy << " in\n" << o.text;
  }
}

TEST(Launcher, IdentifiesARealLogWithoutExoidFullAndNamesWhatASimulatorCommandNeeds) {
  const fs::path dir = fs::temp_directory_path() / ("exoid_launcher_" + std::to_string(::getpid()));
  fs::create_directories(dir / "bin");
  const fs::path alone = dir / "bin" / "exoid";
  fs::copy_file(EXOID_BINARY, alone, fs::copy_options::overwrite_existing);
  const std::string log = kLogDir + "design_A0_20220815_trajectory_11.csv.gz";
  Outcome o = shell(alone.string() + " identify --profile " + kLogDir + "profile.toml --data " + log + " --method ls");
  EXPECT_EQ(o.rc, 0) << o.text;
  EXPECT_NE(o.text.find("Mxt"), std::string::npos) << o.text;
  o = shell(alone.string() + " simulate --out " + (dir / "x.csv").string());
  EXPECT_EQ(o.rc, 2) << o.text;
  EXPECT_NE(o.text.find("exoid simulate: needs the simulator part of exoid (exoid-full; looked in"), std::string::npos) << o.text;
  EXPECT_FALSE(fs::exists(dir / "x.csv"));
  // Beside exoid-full, the same arguments give what exoid-full gives.
  const std::string full = (fs::path(EXOID_BINARY).parent_path() / "exoid-full").string();
  EXPECT_EQ(shell(std::string(EXOID_BINARY) + " simulate --help").text, shell(full + " simulate --help").text);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace exoid::experiments
