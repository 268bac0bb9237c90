// `exoid sweep` / `exoid merge` in-process: determinism across threads, shards + merge, resume.
#include "exoid/experiments/sweep/sweep_runner.hpp"
#include "exoid/experiments/sweep/sweep_summary.hpp"
#include "sweep_test_support.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
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
  // Noise-free cell: the noise-limited std (CRB) is 0 and no ratio is reported.
  EXPECT_EQ(s["conditions"][0]["methods"]["ls"]["parameters"]["Mxt"]["crb_std"].get<double>(), 0.0);
  EXPECT_TRUE(s["conditions"][0]["methods"]["ls"]["rms_error_over_crb_max"].is_null());
  EXPECT_GT(s["conditions"][1]["methods"]["ls"]["parameters"]["Mxt"]["crb_std"].get<double>(), 0.0);
  // Coverage of estimate -+ 1.96 CRB std: over the noisy cell's two seeds; none where the CRB is 0.
  EXPECT_EQ(s["conditions"][1]["methods"]["ls"]["parameters"]["Mxt"]["coverage95"]["n"], 2);
  EXPECT_EQ(s["conditions"][0]["methods"]["ls"]["parameters"]["Mxt"]["coverage95"]["n"], 0);
  EXPECT_NE(slurp(d + "/summary.md").find("Coverage: seeds (%) whose estimate -+ 1.96 CRB std held the truth"), std::string::npos);
  const auto& rp = s["conditions"][1]["methods"]["rls-pso"];
  EXPECT_EQ(rp["n"], 2);
  EXPECT_EQ(rp["vs_ls"]["torque_err_mean"]["n"], 2);
  EXPECT_TRUE(rp["vs_ls"]["torque_err_mean"].contains("p_holm"));
  const double mean = rp["metrics"]["torque_err_mean"]["mean"];
  EXPECT_LE(rp["metrics"]["torque_err_mean"]["ci95_low"].get<double>(), mean);
  EXPECT_GE(rp["metrics"]["torque_err_mean"]["ci95_high"].get<double>(), mean);
  // Every RLS-PSO run carries its optimality gaps, against the box and the unconstrained optimum;
  // the box optimum is never worse than what PSO found inside the box.
  EXPECT_GE(rp["metrics"]["gap_box_max"]["mean"].get<double>(), -1e-9);
  EXPECT_GE(rp["metrics"]["gap_unconstrained_max"]["mean"].get<double>(), rp["metrics"]["gap_box_max"]["mean"].get<double>() - 1e-9);
  // runs.csv carries per-parameter, CRB-normalised and torque-space errors.
  const std::string header = runs.substr(0, runs.find('\n'));
  for (const char* col : {"rel_err_Mxt", "rel_err_rigid_fv2", "err_over_crb_Js", "crb_std_fc1", "torque_err_hip", "gap_box_max"}) {
    EXPECT_NE(header.find(col), std::string::npos) << col;
  }
  EXPECT_EQ(slurp(d + "/summary.json").find("wall_time"), std::string::npos);
}

// summary.json is the typed summary serialised at the edge: the job files summarised again give
// the same JSON, and the typed fields say what the tables show.
TEST(Sweep, SummaryJsonIsTheTypedSummarySerialised) {
  const std::string& d = referenceSweep();
  const SweepLayout layout = layoutFromJson(nlohmann::json::parse(slurp(d + "/config.json")));
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(d + "/runs")) {
    if (e.path().filename().string().rfind("job-", 0) == 0) names.push_back(e.path().string());
  }
  std::sort(names.begin(), names.end());
  std::vector<nlohmann::json> jobs;
  for (const std::string& n : names) jobs.push_back(nlohmann::json::parse(slurp(n)));
  const SweepSummary s = summarizeSweep(layout, jobs);
  EXPECT_EQ(toJson(s), nlohmann::json::parse(slurp(d + "/summary.json")));
  ASSERT_EQ(s.cells.size(), 2u);
  const CellSummary& noisy = s.cells[1];
  EXPECT_EQ(noisy.condition.torque_noise_Nm, 0.5);
  ASSERT_EQ(noisy.methods.size(), 5u);
  EXPECT_FALSE(noisy.method("ls").vs_ls);
  ASSERT_TRUE(noisy.method("rls-pso").vs_ls);
  EXPECT_EQ(noisy.method("rls-pso").vs_ls->torque_err_mean.n, 2);
  EXPECT_EQ(noisy.method("rls-pso").n, 2);
  EXPECT_FALSE(noisy.method("ls").vs_paper_trajectories);  // no optimised cells here
  EXPECT_EQ(noisy.find("idim-iv"), nullptr);
  EXPECT_THROW(noisy.method("idim-iv"), std::out_of_range);
  EXPECT_STREQ(metricName(SweepMetric::kTorqueErrMean), "torque_err_mean");
  EXPECT_STREQ(metricName(SweepMetric::kValRms), "val_rms");
}

// The trajectory axis end to end: each optimised cell is compared with its paper twin over the
// same seeds, and the paired means are the two cells' own means.
TEST(Sweep, OptimisedCellsArePairedWithTheirPaperTwins) {
  const std::string d = freshDir("sweep_trajectories");
  ASSERT_EQ(runExoid({"sweep", "--out", d, "--noise-tau", "0.5", "--vibration", "0", "--cylinder-mass-scale", "1", "--seeds", "3",
                      "--duration", "5", "--methods", "ls,rls-pso", "--pso-iterations", "200", "--trajectories",
                      "paper,optimised", "--no-plots"}),
            0);
  const nlohmann::json s = nlohmann::json::parse(slurp(d + "/summary.json"));
  ASSERT_EQ(s["conditions"].size(), 2u);
  const auto& paper = s["conditions"][0];
  const auto& opt = s["conditions"][1];
  EXPECT_EQ(paper["condition"]["trajectories"], "paper");
  EXPECT_EQ(opt["condition"]["trajectories"], "optimised");
  EXPECT_FALSE(paper["methods"]["ls"].contains("vs_paper_trajectories"));
  const auto& v = opt["methods"]["ls"]["vs_paper_trajectories"];
  EXPECT_EQ(v["paper_cell"], 0);
  EXPECT_EQ(v["torque_err_mean"]["n"], 3);
  EXPECT_DOUBLE_EQ(v["torque_err_mean"]["paper_mean"].get<double>(), paper["methods"]["ls"]["metrics"]["torque_err_mean"]["mean"].get<double>());
  EXPECT_DOUBLE_EQ(v["torque_err_mean"]["optimised_mean"].get<double>(), opt["methods"]["ls"]["metrics"]["torque_err_mean"]["mean"].get<double>());
  EXPECT_TRUE(v["parameters"]["Js"].contains("p_holm"));
  // The same seeds: the runs of replicate r carry the same seed in both cells.
  const std::string runs = slurp(d + "/runs.csv");
  EXPECT_NE(runs.find("optimised"), std::string::npos);
  EXPECT_NE(slurp(d + "/summary.md").find("Optimised vs the paper's identification trajectories"), std::string::npos);
  const nlohmann::json j0 = nlohmann::json::parse(slurp(d + "/runs/job-00000-0001.json"));
  const nlohmann::json j1 = nlohmann::json::parse(slurp(d + "/runs/job-00001-0001.json"));
  EXPECT_EQ(j0["seed"], j1["seed"]);
  // Every run of one cell failed (the review found the per-parameter comparison then indexed past
  // the failed cell's parameters): each cell keeps X's 10 parameters, the failed side's numbers
  // are missing (null), the other side's stand.
  const SweepLayout layout = layoutFromJson(nlohmann::json::parse(slurp(d + "/config.json")));
  for (int failed_cell : {0, 1}) {
    std::vector<nlohmann::json> jobs;
    for (int cell : {0, 1}) {
      for (int rep = 0; rep < 3; ++rep) {
        char name[64];
        std::snprintf(name, sizeof name, "/runs/job-%05d-%04d.json", cell, rep);
        nlohmann::json j = nlohmann::json::parse(slurp(d + name));
        if (cell == failed_cell) j = {{"cell", cell}, {"replicate", rep}, {"seed", j["seed"]}, {"status", "error"}, {"message", "injected"},
                                      {"methods", nlohmann::json::array()}, {"wall_time_s", 0.0}};
        jobs.push_back(j);
      }
    }
    const SweepSummary summary = summarizeSweep(layout, jobs);
    ASSERT_EQ(summary.cells.size(), 2u);
    for (const CellSummary& c : summary.cells) EXPECT_EQ(c.parameters.size(), 10u);
    const MethodSummary& ls = summary.cells[1].method("ls");
    ASSERT_TRUE(ls.vs_paper_trajectories);
    ASSERT_EQ(ls.vs_paper_trajectories->parameters.size(), 10u);
    EXPECT_EQ(ls.vs_paper_trajectories->parameters[0].test.n, 0);
    EXPECT_EQ(summary.cells[static_cast<std::size_t>(failed_cell)].method("ls").n, 0);
    EXPECT_EQ(summary.cells[static_cast<std::size_t>(1 - failed_cell)].method("ls").n, 3);
    const std::string out = freshDir("sweep_failed_cell");
    std::filesystem::create_directories(out);
    EXPECT_NO_THROW(writeSweepTables(layout, jobs, out));
  }
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
