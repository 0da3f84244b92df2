#pragma once
// How LDIs are sampled and lit when baked (ldi_baker.h), kept apart from the baker so that
// scene presets and files can name them without Embree.

#include <cstdint>

#include <glm/vec3.hpp>

namespace terralod::veg {

struct Lighting {
  glm::vec3 toSun{-0.45f, -0.45f, 0.77f};  ///< unit, towards the sun
  float sun = 0.85f, sky = 0.45f;
  uint32_t occlusionRays = 8;
  float occlusionDistance = 1.0f;  ///< metres: farther surfaces do not darken
};

struct SamplingSettings {
  uint32_t raysPerPixel = 4;    ///< a square number: stratified jitter
  float layerTolerance = 1.5f;  ///< in pixels: hits closer in depth are one layer
  /// Depths are rounded to this (in pixels; the 20-bit field could hold micrometres, which
  /// cost bytes and no picture shows).
  float depthStep = 1.0f / 16;
  uint64_t seed = 1;
  /// Keep only surfaces over the centre tile (LDIs); pictures of a tile in context keep all.
  bool centreTileOnly = true;
};

}  // namespace terralod::veg
