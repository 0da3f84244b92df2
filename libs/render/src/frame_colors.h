#pragma once
// The colours a frame derives from its style, shared by the sky and the terrain passes.

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include "terralod/render/terrain_style.h"

namespace terralod {

/// The background (the sky overhead) as floats, sRGB.
inline glm::vec3 backgroundColor(const TerrainStyle& style) {
  return {style.background[0] / 255.0f, style.background[1] / 255.0f, style.background[2] / 255.0f};
}

/// Haze: the background lightened towards white, as distant air looks (sRGB).
inline glm::vec3 hazeColor(const TerrainStyle& style) {
  return glm::mix(backgroundColor(style), glm::vec3(0.92f, 0.93f, 0.95f), 0.55f);
}

}  // namespace terralod
