#pragma once
// The `exoid` a user runs. Reading a log needs no simulator, so `exoid` itself is built without
// MuJoCo, OSMesa, urdfdom or ffmpeg (nothing of them is loaded when it starts) and runs identify
// and identifiability on the built-in leg's logs; every other command, any --help and a robot
// model (--model) go to exoid-full, the same command line with the simulator,
// which it replaces itself with (execv: same arguments, same exit code, same output).
#include <string>
#include <vector>

namespace exoid::experiments {

/// The commands exoid-full runs and the light `exoid` does not have.
const std::vector<std::string>& simulatorCommands();

/// Whether these arguments (argv without argv[0]) need exoid-full: a command other than identify
/// and identifiability, any help, or a model's options (--model, --plot, --armature, --stage).
bool needsFullBinary(const std::vector<std::string>& args);

/// exoid-full beside this executable, else in ../libexec (the installed layout); empty if neither.
/// `looked` (if given) receives the places looked at, for the message when it is missing.
std::string fullBinaryPath(std::string* looked = nullptr);

/// main() of `exoid`: runs the light commands here, replaces itself with exoid-full for the rest.
int runLauncher(int argc, char** argv);

}  // namespace exoid::experiments
