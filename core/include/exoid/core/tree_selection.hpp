#pragma once
// Which serial chain of a robot's tree to take: the options --base, --tip and --lock of every
// command that reads a robot, the Python load_chain's base, tip and lock, a sweep's [sweep] keys.
#include <map>
#include <string>

namespace exoid::core {

/// From link `base` (default: the file's root; MJCF: a body, default the world) down to link `tip`
/// (default: the one leaf of a serial chain). Moving branches hanging from the base (or above it)
/// are left out; a moving branch off a chain link is refused unless its joint is in `locks`
/// (joint -> position, rad or m), which lumps it into the link at that posture. A lock on a joint
/// of the chain's own path holds it there (the chain then has one joint fewer).
struct ChainSelection {
  std::string base, tip;
  std::map<std::string, double> locks;
  bool empty() const { return base.empty() && tip.empty() && locks.empty(); }
  /// The options as given: "--base B --tip T --lock j=0.5" ("" when empty).
  std::string options() const;
  /// options(), or "none" when empty: a record's metadata 'chain_selection'.
  std::string label() const { return empty() ? "none" : options(); }
  /// Adds one lock from "JOINT=VALUE". Throws std::invalid_argument saying what was expected.
  void addLock(const std::string& joint_equals_value);
};

/// The selection of options() or label() text ("--base B --tip T --lock j=0.5", "none", "").
/// Throws std::invalid_argument naming what it could not read.
ChainSelection parseChainSelection(const std::string& text);

}  // namespace exoid::core
