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

// Periodic value noise in [-1, 1], evaluated for the whole texture at once: a lattice of
// `period` cells across the texture, corner values hashed from the wrapped lattice
// coordinates, quintic interpolation. Layers are size * size floats, row by row.
class PeriodicNoise {
 public:
  PeriodicNoise(int size, uint32_t seed) : mSize(size), mSeed(seed) {}

  using Layer = std::vector<float>;

  Layer value(int period, uint32_t octaveSeed) const {
    Layer out(size_t(mSize) * size_t(mSize), 0.0f);
    addOctave(out, period, octaveSeed, 1.0f);
    return out;
  }

  /// Octaves from `period` doubling, amplitudes halving, normalised to about [-1, 1].
  Layer fbm(int period, int octaves, uint32_t octaveSeed) const {
    Layer out(size_t(mSize) * size_t(mSize), 0.0f);
    float norm = 0, amplitude = 1;
    for (int o = 0; o < octaves; ++o) norm += amplitude, amplitude *= 0.5f;
    amplitude = 1.0f / norm;
    for (int o = 0; o < octaves; ++o, amplitude *= 0.5f)
      addOctave(out, period << o, octaveSeed + uint32_t(o) * 7919U, amplitude);
    return out;
  }

 private:
  void addOctave(Layer& out, int period, uint32_t octaveSeed, float amplitude) const {
    period = std::clamp(period, 1, mSize);
    std::vector<float> lattice(size_t(period) * size_t(period));
    for (int j = 0; j < period; ++j)
      for (int i = 0; i < period; ++i) {
        const uint32_t h = hash32(uint32_t(i) * 0x9e3779b1U ^
                                  hash32(uint32_t(j) ^ mSeed ^ octaveSeed * 0x85ebca6bU));
        lattice[size_t(j) * size_t(period) + size_t(i)] = float(double(h) / 2147483647.5 - 1.0);
      }
    // Per column (and, the same, per row): the lattice cell and the eased fraction.
    std::vector<int> cell0(static_cast<size_t>(mSize)), cell1(static_cast<size_t>(mSize));
    std::vector<float> ease(static_cast<size_t>(mSize));
    for (int x = 0; x < mSize; ++x) {
      const double u = (double(x) + 0.5) * period / mSize;
      const int i = int(std::floor(u));
      const double t = u - i;
      ease[size_t(x)] = float(t * t * t * (t * (t * 6 - 15) + 10));
      cell0[size_t(x)] = ((i % period) + period) % period;
      cell1[size_t(x)] = (cell0[size_t(x)] + 1) % period;
    }
    for (int y = 0; y < mSize; ++y) {
      const float* r0 = lattice.data() + size_t(cell0[size_t(y)]) * size_t(period);
      const float* r1 = lattice.data() + size_t(cell1[size_t(y)]) * size_t(period);
      const float fy = ease[size_t(y)];
      float* o = out.data() + size_t(y) * size_t(mSize);
      for (int x = 0; x < mSize; ++x) {
        const int i0 = cell0[size_t(x)], i1 = cell1[size_t(x)];
        const float fx = ease[size_t(x)];
        const float a = r0[i0] + (r0[i1] - r0[i0]) * fx, b = r1[i0] + (r1[i1] - r1[i0]) * fx;
        o[x] += amplitude * (a + (b - a) * fy);
      }
    }
  }

  int mSize;
  uint32_t mSeed;
};

// The pattern as offsets per channel (in 0..255 units): pixel i's are out[3 i .. 3 i + 2].
std::vector<float> pattern(Kind kind, const PeriodicNoise& n, int size) {
  const double tau = 2 * std::numbers::pi;
  const size_t pixels = size_t(size) * size_t(size);
  std::vector<float> out(pixels * 3);
  auto each = [&](auto&& f) {  // f(x, y, i) -> {r, g, b}
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const size_t i = size_t(y) * size_t(size) + size_t(x);
        const std::array<float, 3> v = f(x, y, i);
        out[i * 3] = v[0], out[i * 3 + 1] = v[1], out[i * 3 + 2] = v[2];
      }
  };
  switch (kind) {
    case Kind::kWater: {
      const auto bend = n.fbm(4, 2, 1), fine = n.fbm(16, 2, 2);
      each([&](int x, int y, size_t i) {
        const double fx = double(x) / size, fy = double(y) / size, b = 1.2 * bend[i];
        const double w = 0.6 * std::sin(tau * (3 * fx + 5 * fy) + b) +
                         0.4 * std::sin(tau * (-4 * fx + 2 * fy) + 0.7 * b);
        const float v = float(9 * w + 3 * fine[i]);
        return std::array<float, 3>{0.7f * v, 0.9f * v, 1.2f * v};
      });
      break;
    }
    case Kind::kRock: {
      const auto bend = n.fbm(4, 2, 3), ridges = n.fbm(8, 3, 4), grain = n.fbm(16, 4, 5);
      each([&](int, int y, size_t i) {
        const double strata = std::sin(tau * (7.0 * y / size + 0.5 * bend[i]));
        const double ridge = 1.0 - std::abs(double(ridges[i]));
        const double crack = std::clamp((ridge - 0.88) / 0.12, 0.0, 1.0);
        const float v = float(24 * strata + 20 * grain[i] - 70 * crack);
        return std::array<float, 3>{v, v, v};
      });
      break;
    }
    case Kind::kGrass: {
      const auto speckle = n.value(size / 2, 6), blotch = n.fbm(8, 3, 7);
      each([&](int, int, size_t i) {
        const float v = 18 * speckle[i] + 12 * blotch[i];
        return std::array<float, 3>{0.8f * v, 1.1f * v, 0.6f * v};
      });
      break;
    }
    case Kind::kSnow: {
      const auto soft = n.fbm(4, 3, 8);
      each([&](int, int, size_t i) {
        const float v = 4 * soft[i];
        return std::array<float, 3>{v, v, 0.8f * v};
      });
      break;
    }
    case Kind::kSoil: {
      const auto blotch = n.fbm(8, 4, 9), grit = n.value(size / 4, 10);
      each([&](int, int, size_t i) {
        const float v = 20 * blotch[i] + 6 * grit[i];
        return std::array<float, 3>{1.05f * v, v, 0.9f * v};
      });
      break;
    }
    case Kind::kGeneric: {
      const auto noise = n.fbm(8, 4, 11);
      each([&](int, int, size_t i) {
        const float v = 16 * noise[i];
        return std::array<float, 3>{v, v, v};
      });
      break;
    }
  }
  return out;
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
  const std::vector<float> offsets = pattern(kind, noise, size);
  std::array<double, 3> mean{};
  for (size_t i = 0; i < pixels * 3; ++i) mean[i % 3] += offsets[i];
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
          const auto byte = uint8_t(v + 0.5);  // v is in [0, 255]
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
