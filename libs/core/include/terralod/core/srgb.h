#pragma once
// The sRGB transfer function (IEC 61966-2-1): 8-bit sRGB-encoded values to linear light and
// back, for colour arithmetic (averages, lighting) and formats that store linear colour.

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace terralod {

/// An 8-bit sRGB value to linear, 0..1.
inline float srgbToLinear(uint8_t c) {
  const float v = float(c) / 255.0f;
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

/// Linear 0..1 (clamped) to an 8-bit sRGB value.
inline uint8_t linearToSrgb(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  const float s = v <= 0.0031308f ? v * 12.92f : 1.055f * std::pow(v, 1 / 2.4f) - 0.055f;
  return uint8_t(std::lround(s * 255.0f));
}

}  // namespace terralod
