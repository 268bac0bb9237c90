// A sweep folder is complete or says so: damaged job files are redone, two processes never share
// a folder, merges refuse conflicting duplicates, failed runs fail the command, counts and seeds
// are range-checked, and a config that would fail every run is refused before any run.
#include "sweep_test_support.hpp"

#include "exoid/experiments/sweep/folder_lock.hpp"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace exoid::experiments {
namespace {

namespace fs = std::filesystem;
using test::expectSameSweep;
using test::freshDir;
using test::referenceSweep;
using test::runExoid;
using test::slurp;
using test::tinySweepArgs;

std::string copyOfReference(const std::string& name) {
  const std::string d = freshDir(name);
  fs::create_directories(d);
  fs::copy(referenceSweep(), d, fs::copy_options::recursive);
  fs::remove(d + "/.lock");
  return d;
}

// Runs exoid in-process, capturing what it prints (stdout and stderr) into `out`.
int runCaptured(const std::vector<std::string>& args, std::string& out) {
  std::ostringstream buffer;
  std::streambuf* old_out = std::cout.rdbuf(buffer.rdbuf());
  std::streambuf* old_err = std::cerr.rdbuf(buffer.rdbuf());
  const int rc = runExoid(args);
  std::cout.rdbuf(old_out);
  std::cerr.rdbuf(old_err);
  out = buffer.str();
  return rc;
}

TEST(SweepIntegrity, TheCompletionMarkerIsWrittenLastAndAFolderWithoutItIsFinished) {
  const std::string d = copyOfReference("marker");
  ASSERT_TRUE(fs::exists(d + "/complete.json"));
  // As after a kill between the tables: summary.json present, the marker and later outputs not.
  fs::remove(d + "/complete.json");
  fs::remove(d + "/summary.md");
  fs::remove(d + "/timing.json");
  std::string log;
  ASSERT_EQ(runCaptured(tinySweepArgs(d), log), 0) << log;
  EXPECT_NE(log.find("writing the missing outputs"), std::string::npos) << log;
  EXPECT_EQ(log.find("nothing to do"), std::string::npos) << log;
  EXPECT_TRUE(fs::exists(d + "/summary.md") && fs::exists(d + "/timing.json") && fs::exists(d + "/complete.json"));
  expectSameSweep(d, referenceSweep());
  ASSERT_EQ(runCaptured(tinySweepArgs(d), log), 0) << log;
  EXPECT_NE(log.find("nothing to do"), std::string::npos) << log;
}

TEST(SweepIntegrity, EmptyOrCorruptJobFilesAreRedoneWithAWarning) {
  const std::string d = copyOfReference("damaged");
  std::ofstream(d + "/runs/job-00000-0001.json", std::ios::trunc);  // zero bytes
  std::ofstream(d + "/runs/job-00001-0000.json", std::ios::trunc) << "{\"cell\": 1, \"replic";
  std::string log;
  ASSERT_EQ(runCaptured(tinySweepArgs(d), log), 0) << log;
  EXPECT_NE(log.find("job-00000-0001.json is damaged (it is empty); redoing that run"), std::string::npos) << log;
  EXPECT_NE(log.find("job-00001-0000.json is damaged ("), std::string::npos) << log;
  EXPECT_NE(log.find("4 runs (2 already finished, resuming)"), std::string::npos) << log;
  expectSameSweep(d, referenceSweep());
}

TEST(SweepIntegrity, ASecondProcessOnTheSameFolderIsRefusedNamingTheHolder) {
  const std::string d = copyOfReference("locked");
  fs::remove(d + "/complete.json");
  const FolderLock holder(d, "exoid sweep (the test's)");
  std::string log;
  EXPECT_EQ(runCaptured(tinySweepArgs(d), log), 1);
  EXPECT_NE(log.find(d + " is in use by exoid sweep (the test's) (pid " + std::to_string(::getpid())), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(d + "/complete.json")) << "the refused process wrote outputs";
}

TEST(SweepIntegrity, MergeRefusesConflictingDuplicatesAndAcceptsIdenticalOnes) {
  const std::string s0 = freshDir("m_shard0"), s1 = freshDir("m_shard1");
  for (const auto& [dir, shard] : {std::pair{s0, "0/2"}, std::pair{s1, "1/2"}}) {
    std::vector<std::string> args = tinySweepArgs(dir);
    args.insert(args.end(), {"--shard", shard, "--threads", "1"});
    ASSERT_EQ(runExoid(args), 0);
  }
  // Shard 0's run (0, 0) also in shard 1's folder, identical but for its wall times: fine.
  std::string job = slurp(s0 + "/runs/job-00000-0000.json");
  const auto wt = job.rfind("\"wall_time_s\": ");
  job.replace(wt, job.find('\n', wt) - wt, "\"wall_time_s\": 123.0");
  std::ofstream(s1 + "/runs/job-00000-0000.json") << job;
  std::string log;
  ASSERT_EQ(runCaptured({"merge", "--no-plots", "--out", freshDir("m_ok"), s0, s1}, log), 0) << log;
  // A different result for the same run: refused, naming both files.
  const auto seed = job.find("\"seed\": ");
  job.replace(seed, job.find(',', seed) - seed, "\"seed\": 1");
  std::ofstream(s1 + "/runs/job-00000-0000.json", std::ios::trunc) << job;
  EXPECT_EQ(runCaptured({"merge", "--no-plots", "--out", freshDir("m_conflict"), s0, s1}, log), 1);
  EXPECT_NE(log.find("hold different results for the same run (cell 0, replicate 0)"), std::string::npos) << log;
  EXPECT_NE(log.find(s0 + "/runs/job-00000-0000.json"), std::string::npos) << log;
  EXPECT_NE(log.find(s1 + "/runs/job-00000-0000.json"), std::string::npos) << log;
}

TEST(SweepIntegrity, FailedRunsFailTheCommandEveryTimeItRuns) {
  const std::string d = copyOfReference("failed");
  fs::remove(d + "/complete.json");
  std::ofstream(d + "/runs/job-00001-0001.json", std::ios::trunc)
      << R"({"cell": 1, "replicate": 1, "seed": 5, "status": "error", "message": "injected failure", "methods": [],)"
      << R"( "condition": {}, "wall_time_s": 0.1})";
  std::string log;
  EXPECT_EQ(runCaptured(tinySweepArgs(d), log), 1);
  EXPECT_NE(log.find("1 of 4 runs failed (e.g. cell 1 replicate 1: injected failure)"), std::string::npos) << log;
  EXPECT_TRUE(fs::exists(d + "/complete.json")) << "the folder is complete: its summary covers the other runs";
  EXPECT_EQ(runCaptured(tinySweepArgs(d), log), 1);
  EXPECT_NE(log.find("nothing to do"), std::string::npos) << log;
  EXPECT_NE(log.find("1 of 4 runs failed"), std::string::npos) << log;
}

TEST(SweepIntegrity, AConfigThatWouldFailEveryRunIsRefusedBeforeAnyRun) {
  const std::string d = freshDir("nyquist");
  const std::string toml = d + ".toml";
  std::ofstream(toml) << "[identification]\ncutoff_hz = 600\n";
  std::vector<std::string> args = tinySweepArgs(d);
  args.insert(args.end(), {"--config", toml});
  std::string log;
  EXPECT_EQ(runCaptured(args, log), 1);
  EXPECT_NE(log.find("'cutoff_hz' = 600 Hz must be below the record's Nyquist frequency, 500 Hz"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(d + "/runs")) << "runs were started";
}

TEST(SweepIntegrity, CountsAndSeedsAreRangeChecked) {
  std::string log;
  std::vector<std::string> args = tinySweepArgs(freshDir("range"));
  args.insert(args.end(), {"--seeds", "2147483647"});
  EXPECT_NE(runCaptured(args, log), 0);
  EXPECT_NE(log.find("--seeds"), std::string::npos) << log;
  EXPECT_NE(log.find("1000000"), std::string::npos) << log;
  args = tinySweepArgs(freshDir("range"));
  args.insert(args.end(), {"--master-seed", "-1"});
  EXPECT_NE(runCaptured(args, log), 0);
  EXPECT_NE(log.find("expected a seed: an integer from 0 to 18446744073709551615, got '-1'"), std::string::npos) << log;
  EXPECT_NE(runCaptured({"simulate", "--seed", "-1", "--out", freshDir("range") + ".csv"}, log), 0);
  EXPECT_NE(log.find("got '-1'"), std::string::npos) << log;
}

}  // namespace
}  // namespace exoid::experiments
