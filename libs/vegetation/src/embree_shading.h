#pragma once
// What the Embree ray casters (the LDI baker, the field tracer) share: colour conversions and
// the device's error handler.

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

namespace terralod::veg {

inline float srgbToLinear(uint8_t c) {
  const float v = float(c) / 255.0f;
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

inline uint8_t linearToSrgb(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  const float s = v <= 0.0031308f ? v * 12.92f : 1.055f * std::pow(v, 1 / 2.4f) - 0.055f;
  return uint8_t(std::lround(s * 255.0f));
}

inline void onEmbreeError(void*, RTCError code, const char* message) {
  // Only misuse or memory exhaustion reach here: nothing a user's data can cause.
  std::fprintf(stderr, "terralod: error: Embree: %s (code %d)\n", message ? message : "?",
               int(code));
  std::abort();
}

}  // namespace terralod::veg
