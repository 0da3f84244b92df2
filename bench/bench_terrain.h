#pragma once
// Deterministic rough terrain for micro-benchmarks: ridged multi-octave value noise, the kind of
// surface that keeps a 1 m error budget busy at every level.

#include <cmath>
#include <cstdint>

#include "terralod/raster/heightfield.h"

namespace terralod::bench {

inline float latticeValue(int32_t x, int32_t y, uint32_t seed) {
  uint32_t h = uint32_t(x) * 374761393u + uint32_t(y) * 668265263u + seed * 2246822519u;
  h = (h ^ (h >> 13)) * 1274126177u;
  h ^= h >> 16;
  return float(h & 0xFFFFFF) / float(0xFFFFFF) * 2.0f - 1.0f;
}

inline float valueNoise(float x, float y, uint32_t seed) {
  const int32_t xi = int32_t(std::floor(x)), yi = int32_t(std::floor(y));
  float fx = x - float(xi), fy = y - float(yi);
  fx = fx * fx * (3 - 2 * fx);
  fy = fy * fy * (3 - 2 * fy);
  const float a = latticeValue(xi, yi, seed), b = latticeValue(xi + 1, yi, seed);
  const float c = latticeValue(xi, yi + 1, seed), d = latticeValue(xi + 1, yi + 1, seed);
  const float top = a + (b - a) * fx, bottom = c + (d - c) * fx;
  return top + (bottom - top) * fy;
}

inline Heightfield roughTerrain(int32_t size) {
  Heightfield h(size, size);
  for (int32_t y = 0; y < size; ++y)
    for (int32_t x = 0; x < size; ++x) {
      float z = 0, amplitude = 600, frequency = 1.0f / 2048, weight = 1;
      for (uint32_t octave = 0; octave < 11; ++octave) {
        float v = 1.0f - std::fabs(valueNoise(x * frequency, y * frequency, octave));
        v *= v;
        z += amplitude * v * weight;
        weight = std::fmin(1.0f, v * 1.5f);
        amplitude *= 0.5f;
        frequency *= 2;
      }
      h(x, y) = z;
    }
  return h;
}

}  // namespace terralod::bench
