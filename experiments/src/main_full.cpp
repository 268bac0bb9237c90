// exoid-full: every command, the simulator's included; `exoid` hands it what it cannot run itself.
#include "exoid/experiments/commands/cli.hpp"
#include "exoid/core/heap.hpp"

int main(int argc, char** argv) {
  exoid::core::tuneHeapForLongLogs(false);  // its simulations run on threads that allocate often: an arena each
  return exoid::experiments::runCli(argc, argv);
}
