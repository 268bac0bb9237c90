#pragma once
namespace exoid::experiments {
/// Parses the command line, runs the subcommand, maps errors to a message and exit code.
int runCli(int argc, char** argv);
}  // namespace exoid::experiments
