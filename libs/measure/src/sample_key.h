#pragma once
// One integer key for a grid sample (x, y): the quality measures' maps of samples.

#include <cstdint>

namespace terralod {

inline uint64_t sampleKey(int64_t x, int64_t y) {
  return (uint64_t(x) << 32) | uint64_t(y);
}

}  // namespace terralod
