#pragma once
// Test hook for crash-safety tests: when the environment variable EXOID_TEST_KILL_AT names this
// point, the process kills itself with SIGKILL right here, as a power cut or an OOM killer would.
// Points: "sweep-tables" (summary.json written, the other tables not), "sweep-plots" (plots
// written, timing and completion marker not). Unset in normal use: one getenv per call.
#include <csignal>
#include <cstdlib>
#include <cstring>

namespace exoid::experiments {

inline void testKillPoint(const char* name) {
  const char* at = std::getenv("EXOID_TEST_KILL_AT");
  if (at != nullptr && std::strcmp(at, name) == 0) std::raise(SIGKILL);
}

}  // namespace exoid::experiments
