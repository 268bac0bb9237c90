// exoid: thin entry point; everything lives in the experiments library.
#include "exoid/experiments/cli.hpp"

int main(int argc, char** argv) { return exoid::experiments::runCli(argc, argv); }
