// exoid-full: every command, the simulator's included; `exoid` hands it what it cannot run itself.
#include "exoid/experiments/commands/cli.hpp"
#include "exoid/core/heap.hpp"

#include <cstring>

int main(int argc, char** argv) {
  // The log commands (a model's identify, identifiability) process a long log's blocks on every
  // thread from one heap, as `exoid` does; the simulations run on threads that allocate often: an
  // arena each.
  const bool log_command = argc > 1 && (std::strcmp(argv[1], "identify") == 0 || std::strcmp(argv[1], "identifiability") == 0);
  exoid::core::tuneHeapForLongLogs(log_command);
  return exoid::experiments::runCli(argc, argv);
}
