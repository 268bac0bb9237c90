#include "exoid/sim/data_dir.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace exoid::sim {

namespace {

namespace fs = std::filesystem;

// A data directory has the model: anything else is a stale or foreign folder.
bool looksRight(const fs::path& dir) {
  std::error_code ec;
  return fs::is_regular_file(dir / "models" / "apal_leg.xml", ec);
}

std::string find() {
  std::string looked;
  if (const char* env = std::getenv("EXOID_DATA_DIR"); env && *env) {
    if (looksRight(env)) return fs::path(env).lexically_normal().string();
    throw std::runtime_error(std::string("EXOID_DATA_DIR=") + env + " has no models/apal_leg.xml (expected exoid's data directory: "
                             "models/, plots/, configs/)");
  }
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path beside = (exe.parent_path() / ".." / "share" / "exoid").lexically_normal();
    if (looksRight(beside)) return beside.string();
    looked += beside.string() + ", ";
  }
  // Loaded into another program (the Python module in python3): the shared object holding this code
  // lives in <build>/python or <prefix>/lib/python3/dist-packages; its ancestors hold share/exoid.
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&looksRight), &info) != 0 && info.dli_fname != nullptr) {
    const fs::path object = fs::weakly_canonical(info.dli_fname, ec);
    if (!ec && object != fs::weakly_canonical(exe, ec)) {
      fs::path dir = object.parent_path();
      for (int up = 0; up < 4 && !dir.empty(); ++up, dir = dir.parent_path()) {
        const fs::path candidate = (dir / ".." / "share" / "exoid").lexically_normal();
        if (looksRight(candidate)) return candidate.string();
      }
      looked += object.parent_path().string() + "/{..,../..,../../..,../../../..}/share/exoid, ";
    }
  }
  const fs::path installed = fs::path(EXOID_INSTALL_DATADIR);
  if (looksRight(installed)) return installed.string();
  looked += installed.string();
  throw std::runtime_error("exoid's data directory (models/, plots/, configs/) not found; looked in " + looked +
                           "; set EXOID_DATA_DIR to it");
}

}  // namespace

const std::string& dataDir() {
  static const std::string dir = find();
  return dir;
}

std::string dataPath(const std::string& relative) {
  try {
    return dataDir() + "/" + relative;
  } catch (const std::runtime_error& e) {
    // Defaults are built before any command runs: a missing data directory must not break
    // commands that do not need it, and the one that does fails naming this path.
    return std::string("<") + e.what() + ">/" + relative;
  }
}

}  // namespace exoid::sim
