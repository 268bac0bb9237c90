#include "exoid/experiments/report/plots.hpp"

#include "exoid/sim/data_dir.hpp"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <sys/wait.h>

namespace exoid::experiments {

namespace {
std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}
}  // namespace

void runPlotScript(const std::string& script, const std::vector<std::string>& args) {
  // Debian's python3 owns python3-matplotlib; a python3 earlier on PATH may not have it.
  const char* python = std::getenv("EXOID_PYTHON") ? std::getenv("EXOID_PYTHON") : "/usr/bin/python3";
  std::string cmd = shellQuote(python) + " " + shellQuote(sim::dataPath("plots/" + script));
  for (const std::string& a : args) cmd += " " + shellQuote(a);
  cmd += " 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
  if (!pipe) throw std::runtime_error("cannot start " + std::string(python) + " for plotting");
  std::string output;
  std::array<char, 512> buf{};
  while (fgets(buf.data(), static_cast<int>(buf.size()), pipe.get())) output += buf.data();
  const int status = pclose(pipe.release());
  if (status != 0) {
    throw std::runtime_error("plotting with " + script + " failed (is python3-matplotlib installed? "
                             "scripts/deps.sh installs it; --no-plots skips figures):\n" + output);
  }
}

}  // namespace exoid::experiments
