#include "exoid/experiments/commands/cli.hpp"

#include "exoid/experiments/commands/help_formatter.hpp"

#include "exoid/experiments/commands/commands.hpp"
#include "exoid/experiments/version.hpp"
#ifdef EXOID_WITH_MUJOCO
#include "exoid/sim/data_dir.hpp"
#endif

#include <algorithm>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

namespace exoid::experiments {

namespace {

// Levenshtein distance, for "did you mean" on a mistyped command.
std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// The first word when it is not an option and names no command: say so, list the commands and
// suggest the nearest (CLI11 alone says "A subcommand is required", naming nothing).
std::string unknownCommandMessage(const CLI::App& app, int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return {};
  const std::string word = argv[1];
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands({})) names.push_back(sub->get_name());
  if (std::find(names.begin(), names.end(), word) != names.end()) return {};
  std::string list, nearest;
  std::size_t best = word.size();
  for (const std::string& n : names) {
    list += (list.empty() ? "" : ", ") + n;
    const std::size_t d = editDistance(word, n);
    if (d < best && d <= 2 + n.size() / 4) {
      best = d;
      nearest = n;
    }
  }
  return "exoid: unknown command '" + word + "'" + (nearest.empty() ? "" : "; did you mean '" + nearest + "'?") +
         "\ncommands: " + list + " (exoid --help; exoid COMMAND --help)";
}

// Where the shipped models and configs are, for --help to name its defaults by their place in it.
std::string shippedDataDir() {
#ifdef EXOID_WITH_MUJOCO
  try {
    return sim::dataDir();
  } catch (const std::exception&) {
    return {};  // no data directory: defaults print as they are, and the commands that need one say so
  }
#else
  return {};
#endif
}

}  // namespace

int runCli(int argc, char** argv) {
  CLI::App app{"exoid: simulation-based validation of dynamic parameter identification (RLS-PSO, LS, PSO)\n"
               "for a 2-link lower-extremity exoskeleton leg. SI units inside; see README.md.",
               "exoid"};  // named, not argv[0]: the usage line reads "exoid simulate", whichever binary runs it
  app.formatter(std::make_shared<HelpFormatter>(shippedDataDir()));  // before the subcommands: they copy it
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
  if (const std::string msg = unknownCommandMessage(app, argc, argv); !msg.empty()) {
    std::cerr << msg << '\n';
    return 2;
  }
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
