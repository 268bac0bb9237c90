#pragma once
// Runs `exoid <args...>` in-process through the same entry point as the binary.
#include "exoid/experiments/commands/cli.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace exoid::test {

inline int runExoid(std::vector<std::string> args) {
  args.insert(args.begin(), "exoid");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  return experiments::runCli(static_cast<int>(argv.size()), argv.data());
}

/// A file's whole content (a missing file fails the test and gives "").
inline std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in.good()) << "missing " << path;
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline nlohmann::json readJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

}  // namespace exoid::test
