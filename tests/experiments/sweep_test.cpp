// `exoid sweep` / `exoid merge` in-process: determinism across threads, shards + merge, resume.
#include "exoid/experiments/sweep_runner.hpp"
#include "sweep_test_support.hpp"

#include <cstdlib>
#include <nlohmann/json.hpp>

namespace exoid::experiments {
namespace {

using test::expectSameSweep;
using test::freshDir;
using test::referenceSweep;
using test::runExoid;
using test::slurp;
using test::tinySweepArgs;

TEST(Sweep, WritesEveryOutputWithOneRowPerRunAndMethod) {
  const std::string& d = referenceSweep();
  for (const char* f : {"runs.csv", "summary.csv", "summary.json", "summary.md", "timing.json", "config.json"}) {
    EXPECT_TRUE(std::filesystem::exists(d + "/" + f)) << f;
  }
  const std::string runs = slurp(d + "/runs.csv");
  // Header + 2 cells x 2 seeds x 5 methods.
  EXPECT_EQ(std::count(runs.begin(), runs.end(), '\n'), 1 + 2 * 2 * 5);
  const nlohmann::json s = nlohmann::json::parse(slurp(d + "/summary.json"));
  ASSERT_EQ(s["conditions"].size(), 2u);
  // Noise-free cell: the Cramer-Rao bound is 0 and no ratio is reported.
  EXPECT_EQ(s["conditions"][0]["crb_std"]["Mxt"].get<double>(), 0.0);
  EXPECT_TRUE(s["conditions"][0]["methods"]["ls"]["rms_error_over_crb_mean"].is_null());
  EXPECT_GT(s["conditions"][1]["crb_std"]["Mxt"].get<double>(), 0.0);
  const auto& rp = s["conditions"][1]["methods"]["rls-pso"];
  EXPECT_EQ(rp["n"], 2);
  EXPECT_EQ(rp["vs_ls"]["err_best_fit"]["n"], 2);
  const double mean = rp["metrics"]["err_best_fit"]["mean"];
  EXPECT_LE(rp["metrics"]["err_best_fit"]["ci95_low"].get<double>(), mean);
  EXPECT_GE(rp["metrics"]["err_best_fit"]["ci95_high"].get<double>(), mean);
  EXPECT_EQ(slurp(d + "/summary.json").find("wall_time"), std::string::npos);
}

TEST(Sweep, OneAndTwoThreadsGiveIdenticalResults) {
  const std::string d = freshDir("one_thread");
  std::vector<std::string> args = tinySweepArgs(d);
  args.insert(args.end(), {"--threads", "1"});
  ASSERT_EQ(runExoid(args), 0);
  expectSameSweep(d, referenceSweep());
}

TEST(Sweep, ShardsMergedEqualASingleRun) {
  const std::string s0 = freshDir("shard0"), s1 = freshDir("shard1"), merged = freshDir("merged");
  for (const auto& [dir, shard] : {std::pair{s0, "0/2"}, std::pair{s1, "1/2"}}) {
    std::vector<std::string> args = tinySweepArgs(dir);
    args.insert(args.end(), {"--shard", shard, "--threads", "1"});
    ASSERT_EQ(runExoid(args), 0);
  }
  // A merge of an incomplete set names what is missing.
  EXPECT_EQ(runExoid({"merge", "--no-plots", "--out", freshDir("merged_partial"), s0}), 1);
  ASSERT_EQ(runExoid({"merge", "--no-plots", "--out", merged, s1, s0}), 0);
  expectSameSweep(merged, referenceSweep());
}

TEST(Sweep, ShardFromSlurmEnvironment) {
  ::setenv("SLURM_ARRAY_TASK_ID", "3", 1);
  ::setenv("SLURM_ARRAY_TASK_COUNT", "4", 1);
  ::setenv("SLURM_ARRAY_TASK_MIN", "2", 1);
  const auto s = shardFromEnvironment();
  ::unsetenv("SLURM_ARRAY_TASK_ID");
  ::unsetenv("SLURM_ARRAY_TASK_COUNT");
  ::unsetenv("SLURM_ARRAY_TASK_MIN");
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->index, 1);
  EXPECT_EQ(s->count, 4);
  EXPECT_THROW(parseShard("2/2"), std::invalid_argument);
  EXPECT_THROW(parseShard("1-2"), std::invalid_argument);
  EXPECT_EQ(parseShard("1/3").count, 3);
}

TEST(Sweep, ResumeRefusesAnotherConfigurationAndAFinishedSweepDoesNothing) {
  const std::string d = freshDir("resume_in_process");
  std::filesystem::create_directories(d);
  std::filesystem::copy(referenceSweep(), d, std::filesystem::copy_options::recursive);
  const auto mtime = std::filesystem::last_write_time(d + "/summary.json");
  ASSERT_EQ(runExoid(tinySweepArgs(d)), 0);  // finished: nothing to do
  EXPECT_EQ(std::filesystem::last_write_time(d + "/summary.json"), mtime);
  std::vector<std::string> other = tinySweepArgs(d);
  other.insert(other.end(), {"--master-seed", "7"});
  EXPECT_EQ(runExoid(other), 1);
  // A missing job file is recomputed identically.
  std::filesystem::remove(d + "/runs/job-00001-0001.json");
  std::filesystem::remove(d + "/summary.json");
  ASSERT_EQ(runExoid(tinySweepArgs(d)), 0);
  expectSameSweep(d, referenceSweep());
}

}  // namespace
}  // namespace exoid::experiments
