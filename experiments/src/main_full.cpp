// exoid-full: every command, the simulator's included; `exoid` hands it what it cannot run itself.
#include "exoid/experiments/commands/cli.hpp"
#include "exoid/experiments/commands/launcher.hpp"

int main(int argc, char** argv) {
  exoid::experiments::tuneHeapForLongLogs();
  return exoid::experiments::runCli(argc, argv);
}
