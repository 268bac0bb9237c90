// exoid: thin entry point. The light command line (no simulator loaded); the rest is exoid-full.
#include "exoid/experiments/commands/launcher.hpp"

int main(int argc, char** argv) { return exoid::experiments::runLauncher(argc, argv); }
