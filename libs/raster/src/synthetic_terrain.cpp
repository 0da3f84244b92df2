#include "terralod/raster/synthetic_terrain.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <vector>

// The per-sample octaves are most of the work and vectorise well; on x86-64 an AVX2 copy is
// chosen at load time when the CPU has it (about 2.8x faster than the SSE2 baseline). Both
// copies do the same IEEE operations in the same order, so they return the same bits.
#if defined(__x86_64__) && defined(__has_attribute)
#if __has_attribute(target_clones)
#define TERRALOD_SYNTH_CLONES __attribute__((target_clones("avx2", "default")))
#endif
#endif
#ifndef TERRALOD_SYNTH_CLONES
#define TERRALOD_SYNTH_CLONES
#endif

namespace terralod {
namespace {

constexpr int32_t kLatticeShift = 3;
constexpr int32_t kLatticeCells = 1 << kLatticeShift;
constexpr int32_t kChunk = 256;
constexpr int kMaxOctaves = 24;

// Octaves of the mountains and hills, in metres; each halves the wavelength.
constexpr double kBaseWavelength = 5000.0;
// Shorter than two cells an octave would only alias.
constexpr double kShortestWavelengthCells = 2.0;
// Octaves this long (16 lattice spacings) lose almost nothing to cubic interpolation.
constexpr double kCoarseWavelengthCells = 16.0 * kLatticeCells;
// Octaves this long are ridged; shorter ones add plain noise scaled by the multifractal's
// weight (rough on the crests, smooth in the valleys) instead of drawing ever smaller ridges,
// which crumples the slopes like paper.
constexpr double kShortestRidgedWavelength = 1000.0;
// Above this wavelength each octave's amplitude falls faster than its wavelength, so that the
// large forms stay smooth; below it amplitude is proportional to wavelength (persistence 1/2,
// Hurst exponent 1), the metre-scale roughness of natural ground. Each fine octave then adds
// the same slope, and 1 m rasters of mountains have mostly 10-40 degree slopes, not cliffs.
constexpr double kRoughnessBreakWavelength = 300.0;
constexpr double kCoarsePersistence = 0.4;
constexpr double kFinePersistence = 0.5;
constexpr double kHillPersistence = 0.45;
// Plain noise spreads less than a ridged signal; this evens out their amplitudes.
constexpr double kDetailGain = 2.0;
// |noise| is rounded to n^2 / (|n| + c) (smooth at 0, |n| - c away from it) over about this many
// lattice spacings: on the lattice because the cubics cannot follow a sharp crease and would
// leave a row of dimples along every ridge, and per sample so that crests look alike at every
// spacing instead of tracing worm-like creases.
constexpr double kCreaseRounding = 1.5;

// Ridged multifractal: |noise| is scaled so that the steepest slopes reach zero height, and
// each octave's weight is the previous octave's signal times the gain.
constexpr float kRidgeSharpness = 1.8f;
constexpr float kRidgeGain = 1.5f;

constexpr double kWarpWavelength = 6000.0;
constexpr double kWarpMetres = 500.0;
constexpr double kMaskWavelength = 14000.0;
constexpr double kValleyWavelength = 8000.0;

// Where the continent mask (about unit standard deviation) turns flats into hills and hills
// into mountains: roughly a fifth of the land is flat and a third mountainous.
constexpr double kFlatsEnd = -0.8;
constexpr double kHillsFull = 0.2;
constexpr double kMountainsStart = -0.3;
constexpr double kMountainsFull = 1.0;

constexpr double kBaseHeight = 260.0;
constexpr double kBaseRange = 80.0;
constexpr double kFlatRelief = 1.5;
constexpr double kHillRelief = 140.0;
constexpr double kMountainRelief = 780.0;
// Valley floors keep this fraction of the mountain height; the notch is this wide in mask units.
constexpr double kValleyFloor = 0.4;
constexpr double kValleyWidth = 0.9;
// Rounds the bottom of the notch (a floor ~200 m wide, wider at coarse spacings) so that the
// lattice's cubics can follow it.
constexpr double kValleyRounding = 0.15;
constexpr double kValleyRoundingPerLatticeMetre = 0.0025;

// Gradient components are 16-bit signed integers; this brings the noise to about [-1, 1]
// (standard deviation ~0.18).
constexpr double kNoiseScale = 1.0 / 32768.0;
// A few octaves of it have a standard deviation of about 1/8.
constexpr double kFbmNormalisation = 8.0;

// Rotations (cosine, sine) between 16 and 74 degrees, from Pythagorean triples so they are
// exact to write down. Consecutive octaves take angles far apart (index i * 3 mod 10), which
// hides the axis-aligned streaks of lattice noise. All lie in the first quadrant, so along a
// row both lattice coordinates of a fine octave increase.
constexpr double kRotations[][2] = {{0.6, 0.8},
                                    {0.8, 0.6},
                                    {5.0 / 13.0, 12.0 / 13.0},
                                    {12.0 / 13.0, 5.0 / 13.0},
                                    {8.0 / 17.0, 15.0 / 17.0},
                                    {15.0 / 17.0, 8.0 / 17.0},
                                    {20.0 / 29.0, 21.0 / 29.0},
                                    {21.0 / 29.0, 20.0 / 29.0},
                                    {7.0 / 25.0, 24.0 / 25.0},
                                    {24.0 / 25.0, 7.0 / 25.0}};
constexpr int kRotationCount = sizeof kRotations / sizeof kRotations[0];
const double* rotation(int octave) {
  return kRotations[octave * 3 % kRotationCount];
}

constexpr uint32_t kColumnPrime = 0x9E3779B1u;
constexpr uint32_t kRowPrime = 0x85EBCA77u;

inline uint32_t mix32(uint32_t h) {
  h ^= h >> 16;
  h *= 0x45D9F3B5u;
  h ^= h >> 15;
  h *= 0x2C1B3C6Du;
  h ^= h >> 16;
  return h;
}

uint64_t mix64(uint64_t h) {
  h ^= h >> 32;
  h *= 0xD6E8FEB86659FD93ull;
  h ^= h >> 29;
  h *= 0xA0761D6478BD642Full;
  h ^= h >> 32;
  return h;
}

// An independent 32-bit seed for each purpose (octave, mask, warp...).
uint32_t deriveSeed(uint64_t seed, uint32_t purpose) {
  return static_cast<uint32_t>(mix64(seed ^ mix64(0x243F6A8885A308D3ull + purpose)));
}

// A fraction in [0, 1) from a seed, to set each octave's lattice off the others.
double seedFraction(uint32_t seed) {
  return double(mix32(seed) >> 8) * (1.0 / 16777216.0);
}

// Hash of lattice corner (ix, iy), from which its gradient is taken.
inline uint32_t cornerHash(uint32_t ix, uint32_t iy, uint32_t seed) {
  return mix32((ix * kColumnPrime) ^ (iy * kRowPrime + seed));
}

// The gradient is the hash's two signed 16-bit halves.
template <typename T>
inline T gradientDot(uint32_t h, T x, T y) {
  const T gx = static_cast<T>(static_cast<int32_t>(h) >> 16);
  const T gy = static_cast<T>(static_cast<int32_t>(h << 16) >> 16);
  return gx * x + gy * y;
}

template <typename T>
inline T fade(T t) {
  return t * t * t * (t * (t * T(6) - T(15)) + T(10));
}

// 2D gradient noise (Perlin's construction with hashed gradients), about [-1, 1].
double gradientNoise(double x, double y, uint32_t seed) {
  const double x0 = std::floor(x), y0 = std::floor(y);
  const double fx = x - x0, fy = y - y0;
  const uint32_t ix = static_cast<uint32_t>(static_cast<int64_t>(x0));
  const uint32_t iy = static_cast<uint32_t>(static_cast<int64_t>(y0));
  const double d00 = gradientDot(cornerHash(ix, iy, seed), fx, fy);
  const double d10 = gradientDot(cornerHash(ix + 1, iy, seed), fx - 1.0, fy);
  const double d01 = gradientDot(cornerHash(ix, iy + 1, seed), fx, fy - 1.0);
  const double d11 = gradientDot(cornerHash(ix + 1, iy + 1, seed), fx - 1.0, fy - 1.0);
  const double sx = fade(fx), sy = fade(fy);
  const double lo = d00 + sx * (d10 - d00);
  const double hi = d01 + sx * (d11 - d01);
  return (lo + sy * (hi - lo)) * kNoiseScale;
}

// A few octaves of gradient noise, each rotated against the previous, scaled to about unit
// standard deviation.
double fbm(double x, double y, int octaves, uint32_t seed) {
  double sum = 0.0, amplitude = 1.0, total = 0.0;
  for (int i = 0; i < octaves; ++i) {
    const double* r = rotation(i);
    const double u = r[0] * x - r[1] * y, v = r[1] * x + r[0] * y;
    sum += amplitude * gradientNoise(u, v, seed + 0x632BE5ABu * uint32_t(i));
    total += amplitude;
    amplitude *= 0.5;
    x *= 2.0;
    y *= 2.0;
  }
  return sum / total * kFbmNormalisation;
}

double smoothstep(double lo, double hi, double x) {
  const double t = std::clamp((x - lo) / (hi - lo), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// Catmull-Rom weights for the kLatticeCells phases between two lattice points. Every value is
// a multiple of 1/1024, so the table is exact in float.
struct CubicWeights {
  float w[4][kLatticeCells];
};

constexpr CubicWeights makeCubicWeights() {
  CubicWeights c{};
  for (int p = 0; p < kLatticeCells; ++p) {
    const double t = double(p) / kLatticeCells, t2 = t * t, t3 = t2 * t;
    c.w[0][p] = float(-0.5 * t3 + t2 - 0.5 * t);
    c.w[1][p] = float(1.5 * t3 - 2.5 * t2 + 1.0);
    c.w[2][p] = float(-1.5 * t3 + 2.0 * t2 + 0.5 * t);
    c.w[3][p] = float(0.5 * t3 - 0.5 * t2);
  }
  return c;
}

constexpr CubicWeights kCubic = makeCubicWeights();

// An octave evaluated on the lattice, in double precision, after the warp and a rotation.
struct CoarseOctave {
  double frequency;  // cycles per metre
  double cosine, sine;
  double offsetX, offsetY;
  double crease;  // rounding of |noise|, in noise units
  double mountainAmplitude, hillAmplitude;
  uint32_t hashSeed;
  bool ridged;
};

// An octave evaluated per sample and unwarped, so that along a row its lattice coordinates are
// affine in the column: (u, v) = column * (columnU, columnV) + row * (rowU, rowV) + offset.
struct FineOctave {
  double columnU, rowU, columnV, rowV;
  double offsetX, offsetY;
  float crease;
  float mountainAmplitude, hillAmplitude;
  uint32_t hashSeed;
  bool ridged;
};

// What the lattice carries: the large-scale terrain and what the fine octaves need to go on.
enum Channel {
  kHeight,    // metres, everything evaluated on the lattice
  kMountain,  // metres of mountain per unit of ridged signal
  kWeight,    // the ridged multifractal's weight for the next octave
  kHill,      // metres of hill per unit of noise
  kChannelCount
};

// Scratch for one row of one chunk. Members of one object never alias, which lets the compiler
// vectorise the loops over them without runtime overlap checks.
struct Chunk {
  alignas(64) float channel[kChannelCount][kChunk];
  alignas(64) float ridged[kChunk];
  alignas(64) float hills[kChunk];
};

template <bool kRidged>
inline void addFineOctave(const FineOctave& o, int64_t anchor, int64_t row, Chunk& chunk) {
  // Both lattice coordinates are split into an integer base and a float fraction at the chunk's
  // anchor, a multiple of kChunk, so the float arithmetic below depends on the sample's column
  // and row only, never on the window.
  const double u = (double(anchor) * o.columnU + double(row) * o.rowU) + o.offsetX;
  const double v = (double(anchor) * o.columnV + double(row) * o.rowV) + o.offsetY;
  const double uFloor = std::floor(u), vFloor = std::floor(v);
  const uint32_t ixBase = static_cast<uint32_t>(static_cast<int64_t>(uFloor));
  const uint32_t iyBase = static_cast<uint32_t>(static_cast<int64_t>(vFloor));
  const float u0 = float(u - uFloor), v0 = float(v - vFloor);
  // Both steps are positive, so truncation floors.
  const float du = float(o.columnU), dv = float(o.columnV);
  const uint32_t seed = o.hashSeed;
  const float mountainAmplitude = o.mountainAmplitude, hillAmplitude = o.hillAmplitude;
  const float scale = float(kNoiseScale), crease = o.crease;
  float* weights = chunk.channel[kWeight];
  for (int j = 0; j < kChunk; ++j) {
    const float tu = u0 + float(j) * du, tv = v0 + float(j) * dv;
    const int32_t iu = static_cast<int32_t>(tu), iv = static_cast<int32_t>(tv);
    const float fx = tu - float(iu), fy = tv - float(iv);
    const float fx1 = fx - 1.0f, fy1 = fy - 1.0f;
    const uint32_t hx0 = (ixBase + uint32_t(iu)) * kColumnPrime, hx1 = hx0 + kColumnPrime;
    const uint32_t hy0 = (iyBase + uint32_t(iv)) * kRowPrime + seed, hy1 = hy0 + kRowPrime;
    const float d00 = gradientDot(mix32(hx0 ^ hy0), fx, fy);
    const float d10 = gradientDot(mix32(hx1 ^ hy0), fx1, fy);
    const float d01 = gradientDot(mix32(hx0 ^ hy1), fx, fy1);
    const float d11 = gradientDot(mix32(hx1 ^ hy1), fx1, fy1);
    const float sx = fade(fx), sy = fade(fy);
    const float lo = d00 + sx * (d10 - d00);
    const float hi = d01 + sx * (d11 - d01);
    const float n = (lo + sy * (hi - lo)) * scale;
    if constexpr (kRidged) {
      const float roundedAbs = n * n / (std::fabs(n) + crease) * kRidgeSharpness;
      // Selects between computed values and never guards arithmetic, so that the loop can be
      // made branch-free (see CMakeLists.txt on -fno-trapping-math).
      const float below = 1.0f - roundedAbs;
      float signal = below > 0.0f ? below : 0.0f;
      signal = signal * signal * weights[j];
      chunk.ridged[j] += signal * mountainAmplitude;
      const float weight = signal * kRidgeGain;
      weights[j] = weight < 1.0f ? weight : 1.0f;
    } else {
      chunk.ridged[j] += n * weights[j] * mountainAmplitude;
    }
    chunk.hills[j] += n * hillAmplitude;
  }
}

// Continues the multifractal per sample with the fine octaves, for one row of one chunk whose
// large-scale channels are already interpolated; leaves the heights in channel[kHeight].
TERRALOD_SYNTH_CLONES
void addFineOctaves(const FineOctave* octaves, size_t count, int64_t anchor, int64_t row,
                    Chunk& chunk) {
  for (int j = 0; j < kChunk; ++j) {
    chunk.ridged[j] = 0.0f;
    chunk.hills[j] = 0.0f;
  }
  for (size_t k = 0; k < count; ++k) {
    if (octaves[k].ridged)
      addFineOctave<true>(octaves[k], anchor, row, chunk);
    else
      addFineOctave<false>(octaves[k], anchor, row, chunk);
  }
  float* height = chunk.channel[kHeight];
  const float* mountain = chunk.channel[kMountain];
  const float* hill = chunk.channel[kHill];
  for (int j = 0; j < kChunk; ++j)
    height[j] += mountain[j] * chunk.ridged[j] + hill[j] * chunk.hills[j];
}

}  // namespace

struct SyntheticTerrain::Octaves {
  uint32_t warpSeedX, warpSeedY, maskSeed, valleySeed;
  std::vector<CoarseOctave> coarse;
  std::vector<FineOctave> fine;

  // The channels at lattice point (row, column), which lies at (column, row) * 8 cells.
  void latticeSample(int64_t row, int64_t column, double spacing,
                     float (&channels)[kChannelCount]) const;
};

SyntheticTerrain::SyntheticTerrain(uint64_t seed, double spacing) : mSeed(seed), mSpacing(spacing) {
  assert(spacing > 0 && std::isfinite(spacing));
  auto octaves = std::make_shared<Octaves>();
  octaves->warpSeedX = deriveSeed(seed, 1);
  octaves->warpSeedY = deriveSeed(seed, 2);
  octaves->maskSeed = deriveSeed(seed, 3);
  octaves->valleySeed = deriveSeed(seed, 4);
  double wavelength = kBaseWavelength;
  double mountainAmplitude = 1.0, hillAmplitude = 1.0;
  for (int i = 0; i < kMaxOctaves && wavelength >= kShortestWavelengthCells * spacing; ++i) {
    const uint32_t hashSeed = deriveSeed(seed, 100 + i);
    const double offsetX = 1024.0 * seedFraction(hashSeed ^ 0x1234567u);
    const double offsetY = 1024.0 * seedFraction(hashSeed ^ 0x7654321u);
    const bool ridged = wavelength >= kShortestRidgedWavelength;
    const double amplitude = ridged ? mountainAmplitude : mountainAmplitude * kDetailGain;
    const double* r = rotation(i);
    const double crease = kCreaseRounding * kLatticeCells * spacing / wavelength;
    if (wavelength >= kCoarseWavelengthCells * spacing) {
      octaves->coarse.push_back({1.0 / wavelength, r[0], r[1], offsetX, offsetY, crease, amplitude,
                                 hillAmplitude, hashSeed, ridged});
    } else {
      const double step = spacing / wavelength;  // lattice units per cell
      octaves->fine.push_back({r[0] * step, -r[1] * step, r[1] * step, r[0] * step, offsetX,
                               offsetY, float(crease), float(amplitude), float(hillAmplitude),
                               hashSeed, ridged});
    }
    mountainAmplitude *=
        wavelength > kRoughnessBreakWavelength ? kCoarsePersistence : kFinePersistence;
    hillAmplitude *= kHillPersistence;
    wavelength *= 0.5;
  }
  mOctaves = std::move(octaves);
}

void SyntheticTerrain::Octaves::latticeSample(int64_t row, int64_t column, double spacing,
                                              float (&channels)[kChannelCount]) const {
  const double cell = kLatticeCells * spacing;
  const double px = double(column) * cell, py = double(row) * cell;

  const double warpFrequency = 1.0 / kWarpWavelength;
  const double wx = px * warpFrequency, wy = py * warpFrequency;
  const double qx = px + kWarpMetres * fbm(wx, wy, 2, warpSeedX);
  const double qy = py + kWarpMetres * fbm(wx, wy, 2, warpSeedY);

  const double maskFrequency = 1.0 / kMaskWavelength;
  const double mask = fbm(qx * maskFrequency, qy * maskFrequency, 3, maskSeed);
  const double hill =
      kFlatRelief + (kHillRelief - kFlatRelief) * smoothstep(kFlatsEnd, kHillsFull, mask);

  // A V-shaped notch along the zero lines of a warped noise: valleys across the ranges.
  const double valleyFrequency = 1.0 / kValleyWavelength;
  const double valleyNoise = fbm(qx * valleyFrequency, qy * valleyFrequency, 2, valleySeed);
  const double rounding = std::max(kValleyRounding, kValleyRoundingPerLatticeMetre * cell);
  const double t = std::sqrt(valleyNoise * valleyNoise + rounding * rounding) / kValleyWidth;
  const double notch = t < 1.0 ? t * (2.0 - t) : 1.0;
  const double mountain = kMountainRelief * smoothstep(kMountainsStart, kMountainsFull, mask) *
                          (kValleyFloor + (1.0 - kValleyFloor) * notch);

  double ridged = 0.0, hills = 0.0, weight = 1.0;
  for (const CoarseOctave& o : coarse) {
    const double u = (o.cosine * qx - o.sine * qy) * o.frequency + o.offsetX;
    const double v = (o.sine * qx + o.cosine * qy) * o.frequency + o.offsetY;
    const double n = gradientNoise(u, v, o.hashSeed);
    if (o.ridged) {
      const double roundedAbs = n * n / (std::fabs(n) + o.crease);
      double signal = 1.0 - std::min(roundedAbs * double(kRidgeSharpness), 1.0);
      signal = signal * signal * weight;
      ridged += signal * o.mountainAmplitude;
      weight = std::min(signal * double(kRidgeGain), 1.0);
    } else {
      ridged += n * weight * o.mountainAmplitude;
    }
    hills += n * o.hillAmplitude;
  }
  const double base = kBaseHeight + kBaseRange * mask;
  channels[kHeight] = float(base + hill * hills + mountain * ridged);
  channels[kMountain] = float(mountain);
  channels[kWeight] = float(weight);
  channels[kHill] = float(hill);
}

void SyntheticTerrain::fillWindow(int64_t column0, int64_t row0, int32_t columns, int32_t rows,
                                  float* out) const {
  if (columns <= 0 || rows <= 0) return;
  assert(column0 >= 0 && row0 >= 0 && column0 + columns - 1 <= kMaxIndex &&
         row0 + rows - 1 <= kMaxIndex);
  const Octaves& octaves = *mOctaves;
  const int64_t anchorFirst = column0 / kChunk * kChunk;
  const int64_t anchorEnd = ((column0 + columns - 1) / kChunk + 1) * kChunk;

  // Lattice points covering the chunks with one more before and two after, for the cubics.
  const int64_t latticeColumn0 = anchorFirst / kLatticeCells - 1;
  const size_t latticeColumns = size_t((anchorEnd - anchorFirst) / kLatticeCells + 3);
  const int64_t latticeRow0 = (row0 >> kLatticeShift) - 1;
  const size_t latticeRows = size_t(((row0 + rows - 1) >> kLatticeShift) + 3 - latticeRow0);
  const size_t latticeSize = latticeRows * latticeColumns;
  std::vector<float> lattice(kChannelCount * latticeSize);
  for (size_t i = 0; i < latticeRows; ++i)
    for (size_t j = 0; j < latticeColumns; ++j) {
      float channels[kChannelCount];
      octaves.latticeSample(latticeRow0 + int64_t(i), latticeColumn0 + int64_t(j), mSpacing,
                            channels);
      for (int c = 0; c < kChannelCount; ++c)
        lattice[c * latticeSize + i * latticeColumns + j] = channels[c];
    }

  std::vector<float> rowChannels(kChannelCount * latticeColumns);
  Chunk chunk;
  for (int64_t r = row0; r < row0 + rows; ++r) {
    // Interpolate the lattice down to this row...
    const int phase = int(r & (kLatticeCells - 1));
    const size_t top = size_t((r >> kLatticeShift) - 1 - latticeRow0);
    const float w0 = kCubic.w[0][phase], w1 = kCubic.w[1][phase], w2 = kCubic.w[2][phase],
                w3 = kCubic.w[3][phase];
    for (int c = 0; c < kChannelCount; ++c) {
      const float* l = lattice.data() + c * latticeSize + top * latticeColumns;
      float* dst = rowChannels.data() + c * latticeColumns;
      for (size_t j = 0; j < latticeColumns; ++j)
        dst[j] = w0 * l[j] + w1 * l[latticeColumns + j] + w2 * l[2 * latticeColumns + j] +
                 w3 * l[3 * latticeColumns + j];
    }
    for (int64_t anchor = anchorFirst; anchor < anchorEnd; anchor += kChunk) {
      // ...then along it to every sample of the chunk.
      const size_t first = size_t((anchor - anchorFirst) / kLatticeCells);
      for (int c = 0; c < kChannelCount; ++c) {
        const float* src = rowChannels.data() + c * latticeColumns + first;
        float* dst = chunk.channel[c];
        for (int q = 0; q < kChunk / kLatticeCells; ++q)
          for (int p = 0; p < kLatticeCells; ++p)
            dst[q * kLatticeCells + p] = kCubic.w[0][p] * src[q] + kCubic.w[1][p] * src[q + 1] +
                                         kCubic.w[2][p] * src[q + 2] + kCubic.w[3][p] * src[q + 3];
      }
      // Cubics overshoot a little; amplitudes and weights must stay in range.
      for (int j = 0; j < kChunk; ++j) {
        const float mountain = chunk.channel[kMountain][j], hill = chunk.channel[kHill][j];
        const float weight = chunk.channel[kWeight][j];
        chunk.channel[kMountain][j] = mountain > 0.0f ? mountain : 0.0f;
        chunk.channel[kHill][j] = hill > 0.0f ? hill : 0.0f;
        chunk.channel[kWeight][j] = weight > 0.0f ? (weight < 1.0f ? weight : 1.0f) : 0.0f;
      }
      addFineOctaves(octaves.fine.data(), octaves.fine.size(), anchor, r, chunk);
      const int64_t from = std::max(anchor, column0);
      const int64_t to = std::min(anchor + kChunk, column0 + columns);
      const float* height = chunk.channel[kHeight];
      std::copy(height + (from - anchor), height + (to - anchor),
                out + size_t(r - row0) * size_t(columns) + size_t(from - column0));
    }
  }
}

float SyntheticTerrain::height(int64_t column, int64_t row) const {
  float h = 0.0f;
  fillWindow(column, row, 1, 1, &h);
  return h;
}

}  // namespace terralod
