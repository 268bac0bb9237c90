#include "exoid/experiments/commands/launcher.hpp"

#include "exoid/experiments/commands/cli.hpp"
#include "exoid/core/heap.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <unistd.h>


namespace exoid::experiments {

namespace fs = std::filesystem;

const std::vector<std::string>& simulatorCommands() {
  static const std::vector<std::string> commands{"simulate", "truth", "reproduce", "sweep", "merge", "excite", "render"};
  return commands;
}

namespace {

// "--model" -> ("--model", next argument); "--model=X" -> ("--model", X).
bool optionValue(const std::vector<std::string>& args, std::size_t i, const std::string& name, std::string* value) {
  const std::string& a = args[i];
  if (a == name) {
    *value = i + 1 < args.size() ? args[i + 1] : std::string();
    return true;
  }
  if (a.rfind(name + "=", 0) == 0) {
    *value = a.substr(name.size() + 1);
    return true;
  }
  return false;
}

}  // namespace

bool needsFullBinary(const std::vector<std::string>& args) {
  if (args.empty()) return true;
  const std::string& command = args.front();
  if (command != "identify" && command != "identifiability") return true;  // and any top-level option
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--") break;
    if (a == "-h" || a == "--help" || a == "--help-all") return true;  // the help lists every option
    std::string value;
    for (const char* model_option : {"--model", "--plot", "--armature", "--stage", "--moving-base-parameters", "--consistency-draws", "--consistency-seed"}) {
      if (optionValue(args, i, model_option, &value)) return true;
    }
  }
  return false;
}

std::string fullBinaryPath(std::string* looked) {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  for (const fs::path& candidate : {exe.parent_path() / "exoid-full", exe.parent_path() / ".." / "libexec" / "exoid-full"}) {
    const fs::path p = candidate.lexically_normal();
    if (::access(p.c_str(), X_OK) == 0) return p.string();
    if (looked) *looked += (looked->empty() ? "" : ", ") + p.string();
  }
  return {};
}

int runLauncher(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (needsFullBinary(args)) {
    std::string looked;
    const std::string full = fullBinaryPath(&looked);
    if (!full.empty()) {
      ::execv(full.c_str(), argv);  // returns only on failure
      std::cerr << "exoid: cannot start " << full << ": " << std::strerror(errno) << "\n";
      return 2;
    }
    const std::vector<std::string>& sim = simulatorCommands();
    if (!args.empty() && std::find(sim.begin(), sim.end(), args.front()) != sim.end()) {
      std::cerr << "exoid " << args.front() << ": needs the simulator part of exoid (exoid-full; looked in " << looked
                << "): this exoid was built without MuJoCo (EXOID_WITH_MUJOCO=OFF) or installed without it\n";
      return 2;
    }
    // Without exoid-full this exoid answers what it can: help, --version, its own commands'
    // refusals of what needs a model.
  }
  core::tuneHeapForLongLogs(true);  // the log commands: a long log's blocks on every thread, from one heap
  return runCli(argc, argv);
}

}  // namespace exoid::experiments
