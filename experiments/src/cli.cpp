#include "exoid/experiments/cli.hpp"

#include "exoid/experiments/commands.hpp"
#include "exoid/experiments/version.hpp"
#include "exoid/ident/dataset.hpp"

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
#endif
#ifdef EXOID_WITH_RENDER
  addRenderCommand(app);
#endif
  const std::string name = app.get_name().empty() ? "exoid" : "exoid";
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);  // usage errors: message and help hint, exit code 2 (CLI11's)
  } catch (const UnusableResult& e) {
    std::cerr << name << ": result not usable: " << e.what() << '\n';
    return 3;
  } catch (const ident::DatasetError& e) {
    std::cerr << name << ": error: " << e.what() << '\n';
    return 1;
  } catch (const std::exception& e) {
    std::cerr << name << ": error: " << e.what() << '\n';
    return 1;
  }
  return 0;
}

}  // namespace exoid::experiments
