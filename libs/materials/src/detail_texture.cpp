#include "terralod/materials/detail_texture.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cctype>
#include <cmath>
#include <numbers>
#include <string>

namespace terralod {
namespace {

enum class Kind { kWater, kRock, kGrass, kSnow, kSoil, kGeneric };

Kind kindOf(const std::string& name) {
  std::string lower = name;
  for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
  auto has = [&](std::initializer_list<const char*> words) {
    for (const char* w : words)
      if (lower.find(w) != std::string::npos) return true;
    return false;
  };
  if (has({"water", "lake", "sea", "river", "ocean"})) return Kind::kWater;
  if (has({"snow", "ice", "glacier", "firn"})) return Kind::kSnow;
  if (has({"rock", "stone", "cliff", "scree", "boulder"})) return Kind::kRock;
  if (has({"grass", "veg", "forest", "meadow", "tree", "wood", "shrub", "crop"}))
    return Kind::kGrass;
  if (has({"soil", "sand", "dirt", "earth", "mud", "bare"})) return Kind::kSoil;
  return Kind::kGeneric;
}

uint32_t hash32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

// Periodic value noise in [-1, 1]: a lattice of `period` cells across the texture, corner
// values hashed from the wrapped lattice coordinates, quintic interpolation.
class PeriodicNoise {
 public:
  PeriodicNoise(int size, uint32_t seed) : mSize(size), mSeed(seed) {}

  float value(int x, int y, int period, uint32_t octaveSeed) const {
    period = std::clamp(period, 1, mSize);
    const double u = (double(x) + 0.5) * period / mSize, v = (double(y) + 0.5) * period / mSize;
    const int i0 = int(std::floor(u)), j0 = int(std::floor(v));
    const double fx = fade(u - i0), fy = fade(v - j0);
    auto corner = [&](int i, int j) {
      i = ((i % period) + period) % period;
      j = ((j % period) + period) % period;
      const uint32_t h = hash32(uint32_t(i) * 0x9e3779b1U ^
                                hash32(uint32_t(j) ^ mSeed ^ octaveSeed * 0x85ebca6bU));
      return double(h) / 2147483647.5 - 1.0;
    };
    const double a = corner(i0, j0), b = corner(i0 + 1, j0), c = corner(i0, j0 + 1),
                 d = corner(i0 + 1, j0 + 1);
    return float((a + (b - a) * fx) + ((c + (d - c) * fx) - (a + (b - a) * fx)) * fy);
  }

  /// Octaves from `period` doubling, amplitudes halving, normalised to about [-1, 1].
  float fbm(int x, int y, int period, int octaves, uint32_t octaveSeed) const {
    double sum = 0, norm = 0, amplitude = 1;
    for (int o = 0; o < octaves; ++o) {
      sum += amplitude * value(x, y, period << o, octaveSeed + uint32_t(o) * 7919U);
      norm += amplitude;
      amplitude *= 0.5;
    }
    return float(sum / norm);
  }

 private:
  static double fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }
  int mSize;
  uint32_t mSeed;
};

// The pattern as an offset per channel (in 0..255 units) at pixel (x, y).
std::array<float, 3> pattern(Kind kind, const PeriodicNoise& n, int size, int x, int y) {
  const double tau = 2 * std::numbers::pi;
  const double fx = double(x) / size, fy = double(y) / size;
  switch (kind) {
    case Kind::kWater: {
      const double bend = 1.2 * n.fbm(x, y, 4, 2, 1);
      const double w = 0.6 * std::sin(tau * (3 * fx + 5 * fy) + bend) +
                       0.4 * std::sin(tau * (-4 * fx + 2 * fy) + 0.7 * bend);
      const float v = float(9 * w + 3 * n.fbm(x, y, 16, 2, 2));
      return {0.7f * v, 0.9f * v, 1.2f * v};
    }
    case Kind::kRock: {
      const double strata = std::sin(tau * (7 * fy + 0.5 * n.fbm(x, y, 4, 2, 3)));
      const double ridge = 1.0 - std::abs(double(n.fbm(x, y, 8, 3, 4)));
      const double crack = std::clamp((ridge - 0.88) / 0.12, 0.0, 1.0);
      const float v = float(24 * strata + 20 * n.fbm(x, y, 16, 4, 5) - 70 * crack);
      return {v, v, v};
    }
    case Kind::kGrass: {
      const double speckle = n.value(x, y, size / 2, 6);
      const double blotch = n.fbm(x, y, 8, 3, 7);
      const float v = float(18 * speckle + 12 * blotch);
      return {0.8f * v, 1.1f * v, 0.6f * v};
    }
    case Kind::kSnow: {
      const float v = 4 * n.fbm(x, y, 4, 3, 8);
      return {v, v, 0.8f * v};
    }
    case Kind::kSoil: {
      const float v = 20 * n.fbm(x, y, 8, 4, 9) + 6 * n.value(x, y, size / 4, 10);
      return {1.05f * v, v, 0.9f * v};
    }
    case Kind::kGeneric:
      break;
  }
  const float v = 16 * n.fbm(x, y, 8, 4, 11);
  return {v, v, v};
}

}  // namespace

DetailTexture makeDetailTexture(const Material& material, int size) {
  assert(size > 0 && (size & (size - 1)) == 0);
  const Kind kind = kindOf(material.name);
  uint32_t seed = 2166136261U;  // FNV-1a of the name, then the id
  for (unsigned char c : material.name) seed = (seed ^ c) * 16777619U;
  seed = hash32(seed ^ (uint32_t(material.id) * 0x9e3779b9U));
  const PeriodicNoise noise(size, kind == Kind::kGeneric ? hash32(material.id + 1U) : seed);

  const size_t pixels = size_t(size) * size_t(size);
  std::vector<float> offsets(pixels * 3);
  std::array<double, 3> mean{};
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const auto p = pattern(kind, noise, size, x, y);
      for (int c = 0; c < 3; ++c) {
        offsets[(size_t(y) * size_t(size) + size_t(x)) * 3 + size_t(c)] = p[size_t(c)];
        mean[size_t(c)] += p[size_t(c)];
      }
    }
  for (double& m : mean) m /= double(pixels);

  DetailTexture texture{size, std::vector<uint8_t>(pixels * 3)};
  for (int c = 0; c < 3; ++c) {
    const double target = material.color[size_t(c)];
    // Shift until the rounded, clamped bytes average to the target; halve the contrast when
    // clamping keeps them from getting there.
    for (double contrast = 1.0;; contrast *= 0.5) {
      double shift = target - contrast * mean[size_t(c)];
      double achieved = 0;
      for (int iteration = 0; iteration < 8; ++iteration) {
        uint64_t sum = 0;
        for (size_t i = 0; i < pixels; ++i) {
          const double v = std::clamp(shift + contrast * offsets[i * 3 + size_t(c)], 0.0, 255.0);
          const auto byte = uint8_t(std::lround(v));
          texture.rgb[i * 3 + size_t(c)] = byte;
          sum += byte;
        }
        achieved = double(sum) / double(pixels);
        if (std::abs(achieved - target) <= 0.5) break;
        shift += target - achieved;
      }
      if (std::abs(achieved - target) <= 1.5 || contrast < 1e-3) break;
    }
  }
  return texture;
}

}  // namespace terralod
