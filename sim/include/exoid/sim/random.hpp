#pragma once
// A self-contained random generator, so the simulated bytes do not depend on the standard
// library's distributions: splitmix64 seeding, xoshiro256** (Blackman & Vigna 2018),
// uniform doubles from the top 53 bits, normals by Box-Muller (both values used).
#include <cstdint>

namespace exoid::sim {

std::uint64_t splitmix64(std::uint64_t& state);

/// Seed of an independent stream `stream` derived from a user seed (so that e.g. turning the
/// torque noise on does not change the angle noise).
std::uint64_t streamSeed(std::uint64_t seed, std::uint64_t stream);

/// Stream ids of streamSeed() used by the simulator.
enum RandomStream : std::uint64_t { kStreamEncoder = 1, kStreamTorque = 2, kStreamFloor = 3, kStreamImu = 4 };

class Rng {
 public:
  explicit Rng(std::uint64_t seed);
  std::uint64_t next();
  /// Uniform in [0, 1).
  double uniform();
  /// Standard normal.
  double normal();

 private:
  std::uint64_t s_[4];
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace exoid::sim
