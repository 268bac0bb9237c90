#pragma once
// Where exoid's data lives at run time (models, plot scripts, sweep configs, shipped designs):
// never a source path compiled in, so a built or installed binary keeps working when the source
// tree moves. Layout: <data>/models, <data>/plots, <data>/configs.
#include <string>

namespace exoid::sim {

/// The data directory, the first of: $EXOID_DATA_DIR (must exist); <the running executable's
/// folder>/../share/exoid (the build tree and an installed prefix both have it); when this code
/// is loaded into another program (the Python module), share/exoid beside an ancestor of the
/// shared object's folder; the install prefix's share/exoid. Throws std::runtime_error listing where it looked.
const std::string& dataDir();

/// dataDir() + "/" + relative, e.g. dataPath("models/apal_leg.xml"); without a data directory,
/// a path that names the problem (opening it fails with that message), never an exception.
std::string dataPath(const std::string& relative);

}  // namespace exoid::sim
