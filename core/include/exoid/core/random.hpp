#pragma once
// exoid's one random generator, so every draw (sensor noise, floor disturbance, PSO, sweep seeds,
// excitation restarts) is the same bytes with every standard library and compiler:
// xoshiro256** (Blackman & Vigna 2018) seeded through splitmix64, uniform doubles from the top 53
// bits, normals by Box-Muller (both values used), and one rule for sub-seeds.
#include <cmath>
#include <cstdint>

namespace exoid::core {

/// One step of splitmix64 (Steele, Lea & Flood 2014): advances `state`, returns the output.
inline std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

/// The seed of sub-stream `index` of `seed` (a sweep cell, a record, a sensor): independent of the
/// order in which sub-streams are made, and of each other for distinct indices.
inline std::uint64_t deriveSeed(std::uint64_t seed, std::uint64_t index) {
  std::uint64_t x = seed ^ (0x9E3779B97F4A7C15ULL * (index + 1));
  return splitmix64(x);
}

class Rng {
 public:
  explicit Rng(std::uint64_t seed) {
    for (auto& s : s_) s = splitmix64(seed);
  }
  std::uint64_t next() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  /// Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Standard normal (Box-Muller; the second value of each pair is kept for the next call).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - uniform();  // in (0, 1]: log(u1) is finite
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double a = 2.0 * M_PI * u2;
    spare_ = r * std::sin(a);
    has_spare_ = true;
    return r * std::cos(a);
  }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t s_[4];
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace exoid::core
