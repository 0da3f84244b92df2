#include "terralod/format/generated_colour.h"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace terralod {
namespace {

constexpr double kRadians = 3.14159265358979323846 / 180.0;

GroundColor mix(GroundColor a, GroundColor b, float t) {
  return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t};
}
float smoothstep(float e0, float e1, float x) {
  const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3 - 2 * t);
}

GroundColor paletteColor(float height) {
  const auto& p = kGroundPalette;
  if (height <= p[0].height) return p[0].color;
  for (size_t i = 1; i < std::size(p); ++i)
    if (height < p[i].height)
      return mix(p[i - 1].color, p[i].color,
                 (height - p[i - 1].height) / (p[i].height - p[i - 1].height));
  return p[std::size(p) - 1].color;
}

float snowCoverBelow(float height, float snowLine) {
  return smoothstep(snowLine, snowLine + kSnowBand, height);
}

}  // namespace

double snowLine(double latitudeDeg) {
  if (std::isnan(latitudeDeg)) latitudeDeg = kUnknownLatitude;
  const double c = std::max(0.0, std::cos(std::clamp(latitudeDeg, -90.0, 90.0) * kRadians));
  return 5200.0 * c * std::sqrt(c);
}

float snowCover(double height, double latitudeDeg) {
  return snowCoverBelow(float(height), float(snowLine(latitudeDeg)));
}

GroundColor groundColorBelow(float height, float slope, float snowLine) {
  GroundColor c = mix(paletteColor(height), kSnowColor, snowCoverBelow(height, snowLine));
  // Steep ground is bare rock at any height; snow does not hold on it.
  return mix(c, kBareRockColor, smoothstep(kRockSlopeStart, kRockSlopeEnd, slope));
}

GroundColor groundColor(double height, float slope, double latitudeDeg) {
  return groundColorBelow(float(height), slope, float(snowLine(latitudeDeg)));
}

GroundColor shadedColour(float height, float slope, float snowLine, float shade) {
  const float v = std::clamp(shade, 0.0f, 1.0f);
  // Below kLandShade the texel is part water: taken as water and open land (shade 1) mixed,
  // continuous with the darkest land at kLandShade.
  const float water = std::clamp(1.0f - v / kLandShade, 0.0f, 1.0f);
  const float land = v >= kLandShade ? v : 1.0f + (kLandShade - 1.0f) * (v / kLandShade);
  const float occlusion =
      kMinOcclusion + (1.0f - kMinOcclusion) * (land - kLandShade) / (1.0f - kLandShade);
  // Darkening linear light by `occlusion` scales display values by occlusion^(1/2.2).
  const float dim = std::pow(occlusion, 1.0f / 2.2f);
  const GroundColor g = groundColorBelow(height, slope, snowLine);
  return mix({g.r * dim, g.g * dim, g.b * dim}, kWaterColor, water);
}

std::vector<float> snowLineSamples(std::span<const double> rowLatitudes, uint32_t rows) {
  std::vector<float> out(kSnowLineSamples);
  for (size_t k = 0; k < out.size(); ++k) {
    double latitude = kUnknownLatitude;
    if (!rowLatitudes.empty() && rows > 0) {
      const double row = double(rows - 1) * double(k) / double(out.size() - 1);
      const size_t i = std::min(size_t(std::lround(row)), rowLatitudes.size() - 1);
      latitude = rowLatitudes[i];
    }
    out[k] = float(snowLine(latitude));
  }
  return out;
}

float snowLineAt(std::span<const float> samples, double t) {
  if (samples.empty()) return float(snowLine(kUnknownLatitude));
  const double x = std::clamp(t, 0.0, 1.0) * double(samples.size() - 1);
  const size_t i = std::min(size_t(x), samples.size() - 1);
  const size_t j = std::min(i + 1, samples.size() - 1);
  return float(samples[i] + (samples[j] - samples[i]) * (x - double(i)));
}

}  // namespace terralod
