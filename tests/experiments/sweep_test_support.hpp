#pragma once
// Shared by the sweep tests: a tiny grid (2 s records, G = 200, 2 cells x 2 seeds), running
// `exoid` in-process or as a child, and comparing sweep folders.
#include "cli_test_support.hpp"
#include "exoid/experiments/commands/cli.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <unistd.h>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace exoid::experiments::test {

inline std::vector<std::string> tinySweepArgs(const std::string& out) {
  return {"sweep", "--out", out, "--noise-tau", "0,0.5", "--vibration", "0", "--cylinder-mass-scale", "1",
          "--seeds", "2", "--duration", "2", "--pso-iterations", "200", "--methods", "ls,rls,pso,rls-pso,lad", "--trajectories", "paper",
          "--no-plots"};
}

using exoid::test::runExoid;
using exoid::test::slurp;

/// runs.csv without its last column (wall_time_s, the one non-deterministic value).
inline std::string runsWithoutWallTime(const std::string& dir) {
  std::istringstream in(slurp(dir + "/runs.csv"));
  std::string line, out;
  while (std::getline(in, line)) out += line.substr(0, line.rfind(',')) + "\n";
  return out;
}

/// Same runs (minus wall time), same summary bytes, same set of job files.
inline void expectSameSweep(const std::string& a, const std::string& b) {
  const std::string runs = runsWithoutWallTime(a);
  EXPECT_GT(std::count(runs.begin(), runs.end(), '\n'), 1);
  EXPECT_EQ(runs, runsWithoutWallTime(b));
  for (const char* f : {"summary.json", "summary.csv", "summary.md", "config.json"}) {
    EXPECT_EQ(slurp(a + "/" + f), slurp(b + "/" + f)) << f;
  }
  std::vector<std::string> ja, jb;
  for (const auto& e : std::filesystem::directory_iterator(a + "/runs")) ja.push_back(e.path().filename().string());
  for (const auto& e : std::filesystem::directory_iterator(b + "/runs")) jb.push_back(e.path().filename().string());
  std::sort(ja.begin(), ja.end());
  std::sort(jb.begin(), jb.end());
  EXPECT_EQ(ja, jb);
}

/// A fresh folder private to this process: ctest runs each test in its own process, in parallel.
inline std::string freshDir(const std::string& name) {
  const std::string d = ::testing::TempDir() + "/exoid_sweep_" + std::to_string(::getpid()) + "_" + name;
  std::filesystem::remove_all(d);
  return d;
}

/// The reference: one single-process run of the tiny sweep (2 threads), computed once per binary.
inline const std::string& referenceSweep() {
  static const std::string dir = [] {
    const std::string d = freshDir("reference");
    std::vector<std::string> args = tinySweepArgs(d);
    args.insert(args.end(), {"--threads", "2"});
    EXPECT_EQ(runExoid(args), 0);
    return d;
  }();
  return dir;
}

}  // namespace exoid::experiments::test
