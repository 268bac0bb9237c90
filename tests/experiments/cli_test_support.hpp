#pragma once
// Runs `exoid <args...>` in-process through the same entry point as the binary.
#include "exoid/experiments/commands/cli.hpp"

#include <string>
#include <vector>

namespace exoid::test {

inline int runExoid(std::vector<std::string> args) {
  args.insert(args.begin(), "exoid");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  return experiments::runCli(static_cast<int>(argv.size()), argv.data());
}

}  // namespace exoid::test
