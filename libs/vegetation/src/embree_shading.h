#pragma once
// What the Embree ray casters (the LDI baker, the field tracer) share: occlusion-ray
// directions and the device's error handler (colour conversions: core/srgb.h).

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "terralod/core/srgb.h"

namespace terralod::veg {

/// Cosine-weighted directions over the hemisphere of a unit normal (ambient-occlusion rays).
class Hemisphere {
 public:
  explicit Hemisphere(const glm::vec3& n)
      : mN(n),
        mT(glm::normalize(std::abs(n.z) < 0.9f ? glm::cross(n, glm::vec3(0, 0, 1))
                                               : glm::cross(n, glm::vec3(1, 0, 0)))),
        mB(glm::cross(n, mT)) {}
  /// The direction for two uniform numbers in [0, 1), drawn in this order.
  glm::vec3 direction(double first, double second) const {
    const float u = float(first), phi = float(2 * std::numbers::pi * second);
    const float r = std::sqrt(u), z = std::sqrt(1 - u);
    return r * std::cos(phi) * mT + r * std::sin(phi) * mB + z * mN;
  }

 private:
  glm::vec3 mN, mT, mB;
};

inline void onEmbreeError(void*, RTCError code, const char* message) {
  // Only misuse or memory exhaustion reach here: nothing a user's data can cause.
  std::fprintf(stderr, "terralod: error: Embree: %s (code %d)\n", message ? message : "?",
               int(code));
  std::abort();
}

}  // namespace terralod::veg
