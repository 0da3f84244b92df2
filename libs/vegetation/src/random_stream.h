#pragma once
// A small fixed pseudo-random generator (splitmix64) for the vegetation's offline steps:
// the same seed gives the same plants, placements and rays on every machine and standard
// library (std::uniform_*_distribution does not promise that).

#include <cstdint>

namespace terralod::veg {

/// splitmix64's finalizer: a well-mixed 64-bit function of a 64-bit value (hashes of tiles).
inline uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

/// One step of splitmix64 (Steele, Lea, Flood 2014): advances `state`, returns the next value.
inline uint64_t splitmix64(uint64_t& state) {
  return mix64(state += 0x9e3779b97f4a7c15ull);
}

class RandomStream {
 public:
  explicit RandomStream(uint64_t seed) : mState(seed) {}

  uint64_t next() { return splitmix64(mState); }
  /// Uniform in [0, 1).
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform in [0, n), n > 0.
  uint32_t below(uint32_t n) { return uint32_t((next() >> 32) * n >> 32); }

 private:
  uint64_t mState;
};

}  // namespace terralod::veg
