#pragma once
// The simulator's random streams: one sub-seed per noise source (core::deriveSeed of the run's
// seed), so that e.g. turning the torque noise on does not change the angle noise.
#include "exoid/core/random.hpp"

namespace exoid::sim {

/// Stream ids of the simulator's noise sources.
enum RandomStream : std::uint64_t { kStreamEncoder = 1, kStreamTorque = 2, kStreamFloor = 3, kStreamImu = 4 };

using core::Rng;

/// The seed of noise source `stream` of a run seeded with `seed`.
inline std::uint64_t streamSeed(std::uint64_t seed, RandomStream stream) { return core::deriveSeed(seed, stream); }

}  // namespace exoid::sim
