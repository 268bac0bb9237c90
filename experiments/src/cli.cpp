#include "exoid/experiments/cli.hpp"

#include "exoid/experiments/commands.hpp"
#include "exoid/experiments/version.hpp"

#include <iostream>

namespace exoid::experiments {

int runCli(int argc, char** argv) {
  CLI::App app{"exoid: simulation-based validation of dynamic parameter identification (RLS-PSO, LS, PSO)\n"
               "for a 2-link lower-extremity exoskeleton leg. SI units inside; see README.md."};
  app.set_version_flag("--version", std::string("exoid ") + kVersion + " (" + kGitRevision + ")");
  app.require_subcommand(1);
  app.fallthrough(false);
  addIdentifyCommand(app);
  addIdentifiabilityCommand(app);
#ifdef EXOID_WITH_MUJOCO
  addSimulateCommand(app);
  addTruthCommand(app);
  addReproduceCommand(app);
  addSweepCommand(app);
  addMergeCommand(app);
  addExciteCommand(app);
#endif
#ifdef EXOID_WITH_RENDER
  addRenderCommand(app);
#endif
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);  // usage errors: message, help hint, CLI11's non-zero code
  } catch (const UnusableResult& e) {
    std::cerr << "exoid: result not usable: " << e.what() << '\n';
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "exoid: error: " << e.what() << '\n';
    return 1;
  }
  return 0;
}

}  // namespace exoid::experiments
